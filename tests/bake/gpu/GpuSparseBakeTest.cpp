// The sparse GPU bake against the sparse CGAL bake and the dense GPU bake of the same grid: the
// band's values, the signs of every grid point (tiles included), batching, determinism, and the
// command line.
//
// Limits: band values within 1e-3 voxel of CGAL (the bound; measured ~1e-6) and within
// 1e-5 voxel of the dense GPU bake (the same float passes); no sign mismatch on a closed mesh;
// the band the same voxels as CGAL's.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <unordered_map>
#include <vector>

#include <gtest/gtest.h>

#include "../gpu/GpuTest.h"
#include "CliRun.h"
#include "TestMeshes.h"
#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/cgal/CgalSparseBaker.h"
#include "sluice/bake/gpu/GpuBaker.h"
#include "sluice/bake/gpu/GpuSparseBaker.h"
#include "sluice/bake/sparse/SparseBaker.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/GridSamples.h"
#include "sluice/format/asset/SdfSampler.h"

namespace {

using namespace sluice;
using namespace sluice::bake;
namespace fs = std::filesystem;

constexpr double kBand = 3.0;

BakeSettings settingsAt(std::uint32_t resolution) {
    BakeSettings s;
    s.grid.resolution = resolution;
    s.grid.padding = 4.0; // >= band + 1: the sparse and dense grids are the same
    return s;
}

ImportedMesh sphere() {
    return testmesh::imported(testmesh::icoSphereSoup({0.013, -0.021, 0.007}, 0.5, 3),
                              "sphere.obj");
}

/// An open box (no top): the winding number decides every sign, no empty ball does.
ImportedMesh openBox() {
    return testmesh::imported(testmesh::boxSoup({-0.4, -0.3, -0.35}, {0.45, 0.3, 0.4}, true),
                              "open-box.obj");
}

/// The band voxels of a sparse asset (|phi| < band, in float as SparseGridBuilder decides), by
/// grid index.
std::unordered_map<std::uint64_t, float> bandVoxels(const format::ColliderAsset& a) {
    std::unordered_map<std::uint64_t, float> out;
    const float band = float(a.meta.bandWidth * a.meta.voxelSize);
    format::forEachStoredSample(a, [&](glm::uvec3 p, float phi) {
        if (std::abs(phi) < band)
            out[a.index(p.x, p.y, p.z)] = phi;
    });
    return out;
}

/// Grid points where the two assets' signs differ, ignoring points within 1e-4 voxel of the
/// surface in either.
std::uint64_t signMismatches(const format::ColliderAsset& a, const format::ColliderAsset& b) {
    const format::SdfSampler sa(a), sb(b);
    const double tiny = 1e-4 * a.meta.voxelSize;
    std::uint64_t mismatches = 0;
    const glm::uvec3 dims = a.meta.dims;
    for (std::uint32_t k = 0; k < dims.z; ++k)
        for (std::uint32_t j = 0; j < dims.y; ++j)
            for (std::uint32_t i = 0; i < dims.x; ++i) {
                const glm::dvec3 p = a.pointPosition(i, j, k);
                const double va = sa.value(p), vb = sb.value(p);
                if (std::abs(va) > tiny && std::abs(vb) > tiny && (va < 0.0) != (vb < 0.0))
                    ++mismatches;
            }
    return mismatches;
}

class GpuSparseBakeTest : public gpu::test::GpuTest {
protected:
    format::ColliderAsset bakeSparse(const ImportedMesh& mesh, std::uint32_t resolution,
                                     const GpuBakeOptions& options = {},
                                     SparseBakeStats* stats = nullptr,
                                     GpuBakeStats* gpuStats = nullptr) {
        auto r = bakeSparseGpu(mesh, settingsAt(resolution), {.band = kBand}, context(), false,
                               options, gpuStats, stats);
        EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message());
        return r.ok() ? std::move(*r) : format::ColliderAsset{};
    }
};

TEST_F(GpuSparseBakeTest, MatchesTheCgalSparseBakeInTheBandAndEverywhereInSign) {
    const ImportedMesh mesh = sphere();
    SparseBakeStats gpuStats, cgalStats;
    const format::ColliderAsset gpuAsset = bakeSparse(mesh, 48, {}, &gpuStats);
    auto cgal = bakeSparseCgal(mesh, settingsAt(48), {.band = kBand}, false, &cgalStats);
    ASSERT_TRUE(cgal.ok()) << cgal.error().message();
    ASSERT_TRUE(gpuAsset.sparse());
    EXPECT_EQ(gpuAsset.meta.bake.backend, "gpu");
    EXPECT_EQ(gpuAsset.meta.dims, cgal->meta.dims);
    EXPECT_EQ(gpuAsset.meta.bandWidth, kBand);
    ASSERT_TRUE(gpuAsset.meta.meshMass.has_value());

    // The GPU's culling understates distances by their rounding bound: the CGAL bricks and at
    // most a few more.
    EXPECT_GE(gpuStats.bricks, cgalStats.bricks);
    EXPECT_LE(gpuStats.bricks, cgalStats.bricks + cgalStats.bricks / 50);
    EXPECT_EQ(gpuStats.voxelsComputed >= cgalStats.voxelsComputed, true);

    const auto gpuBand = bandVoxels(gpuAsset), cgalBand = bandVoxels(*cgal);
    ASSERT_GT(cgalBand.size(), 10000u);
    std::uint64_t missing = 0;
    double maxError = 0.0;
    for (const auto& [index, ref] : cgalBand) {
        const auto it = gpuBand.find(index);
        if (it == gpuBand.end()) {
            ++missing;
            continue;
        }
        maxError = std::max(maxError, std::abs(double(it->second) - ref) / gpuAsset.meta.voxelSize);
    }
    EXPECT_EQ(missing, 0u);
    EXPECT_EQ(gpuBand.size(), cgalBand.size());
    EXPECT_LE(maxError, 1e-3);
    EXPECT_EQ(signMismatches(gpuAsset, *cgal), 0u);
}

TEST_F(GpuSparseBakeTest, EqualsTheDenseGpuBakeOfTheSameGrid) {
    for (const ImportedMesh& mesh : {sphere(), openBox()}) {
        SCOPED_TRACE(mesh.sourceFile);
        const format::ColliderAsset sparse = bakeSparse(mesh, 40);
        auto dense = bakeGpu(mesh, settingsAt(40), context());
        ASSERT_TRUE(dense.ok()) << dense.error().message();
        ASSERT_EQ(sparse.meta.dims, dense->meta.dims);
        ASSERT_EQ(sparse.meta.origin, dense->meta.origin);
        const double voxel = sparse.meta.voxelSize;
        double maxError = 0.0;
        std::uint64_t band = 0;
        for (const auto& [index, phi] : bandVoxels(sparse)) {
            maxError = std::max(maxError, std::abs(double(phi) - dense->distances[index]) / voxel);
            ++band;
        }
        EXPECT_GT(band, 5000u);
        EXPECT_LE(maxError, 1e-5);
        EXPECT_EQ(signMismatches(sparse, *dense), 0u);
    }
}

TEST_F(GpuSparseBakeTest, DeepInsideIsNegativeAndFarOutsidePositive) {
    const format::ColliderAsset a = bakeSparse(sphere(), 48);
    const format::SdfSampler sampler(a);
    const double band = kBand * a.meta.voxelSize;
    EXPECT_FLOAT_EQ(sampler.value({0.013, -0.021, 0.007}), float(-band));
    EXPECT_FLOAT_EQ(sampler.value(a.meta.origin), float(band));
}

TEST_F(GpuSparseBakeTest, SmallBatchesGiveTheSameBytesAndSoDoesASecondBake) {
    const ImportedMesh mesh = sphere();
    SparseBakeStats stats;
    GpuBakeStats gpuStats;
    const format::ColliderAsset whole = bakeSparse(mesh, 48, {}, &stats);
    // 8 bricks per batch, 4 work groups per slab: dozens of batches and slabs.
    GpuBakeStats smallStats;
    const format::ColliderAsset batched =
        bakeSparse(mesh, 48, {.sparseBricksPerBatch = 8}, nullptr, &smallStats);
    ASSERT_GT(stats.bricks, 8u * 20u);
    const auto a = format::encodeAsset(whole), b = format::encodeAsset(batched);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->bytes, b->bytes);
    const format::ColliderAsset again = bakeSparse(mesh, 48, {}, nullptr, &gpuStats);
    const auto c = format::encodeAsset(again);
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(a->bytes, c->bytes);
    EXPECT_GT(smallStats.dispatches, 4 * gpuStats.dispatches);
    // Empty balls decide most band voxels of a closed mesh; the winding number the rest.
    EXPECT_GT(gpuStats.pendingPoints, 0u);
    EXPECT_LT(gpuStats.pendingPoints, stats.voxelsComputed);
}

TEST_F(GpuSparseBakeTest, GpuMemoryDoesNotGrowWithTheGrid) {
    const ImportedMesh mesh = sphere();
    GpuBakeStats small, large;
    SparseBakeStats smallSparse, largeSparse;
    (void)bakeSparse(mesh, 32, {}, &smallSparse, &small);
    (void)bakeSparse(mesh, 96, {}, &largeSparse, &large);
    EXPECT_GT(largeSparse.bricks, 4 * smallSparse.bricks);
    EXPECT_EQ(small.gpuBytes, large.gpuBytes);
}

TEST_F(GpuSparseBakeTest, ABufferOverTheLimitIsRefusedCleanly) {
    auto r = bakeSparseGpu(sphere(), settingsAt(32), {.band = kBand}, context(), false,
                           {.maxBufferBytes = 1 << 20});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::SizeOverflow);
    EXPECT_NE(r.error().detail.find("sphere.obj"), std::string::npos);
}

TEST_F(GpuSparseBakeTest, AGridTooLongForFloatCoordinatesIsRefusedBeforeBaking) {
    // 20,000 voxels along x: past 16,384, where float rounding would outgrow the culling's margin.
    BakeSettings s;
    s.grid.voxelSize = 1.0 / 20000.0;
    s.grid.resolution = 0;
    const ImportedMesh rod =
        testmesh::imported(testmesh::boxSoup({0, 0, 0}, {1.0, 2e-4, 2e-4}), "rod.obj");
    auto r = bakeSparseGpu(rod, s, {.band = kBand}, context());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::SizeOverflow);
    EXPECT_NE(r.error().detail.find("rod.obj"), std::string::npos) << r.error().detail;
    EXPECT_NE(r.error().detail.find("--backend cgal"), std::string::npos) << r.error().detail;
}

TEST_F(GpuSparseBakeTest, TheCommandLineBakesSparseOnTheGpuAndValidates) {
    const fs::path dir = testmesh::tempDir("gpu-sparse-cli");
    const fs::path mesh = dir / "ball.obj";
    ASSERT_TRUE(testmesh::writeObj(testmesh::icoSphereSoup({0, 0, 0}, 0.5, 3), mesh));
    const fs::path out = dir / "ball.slc";
    const auto bake =
        clirun::runBake(dir, {"bake", mesh.string(), "-o", out.string(), "--sparse", "--band", "4",
                              "--resolution", "40", "--backend", "gpu", "--quiet"});
    ASSERT_EQ(bake.code, 0) << bake.err;
    auto asset = format::readAsset(out.string());
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    EXPECT_TRUE(asset->sparse());
    EXPECT_EQ(asset->meta.bake.backend, "gpu");
    EXPECT_EQ(asset->meta.bandWidth, 4.0);
    const auto validate =
        clirun::runBake(dir, {"validate", out.string(), mesh.string(), "--quiet"});
    EXPECT_EQ(validate.code, 0) << validate.out << validate.err;
    EXPECT_NE(validate.out.find("PASS"), std::string::npos) << validate.out;

    // Bad input on the way: nothing written, exit 2.
    const fs::path bad = dir / "bad.slc";
    EXPECT_EQ(clirun::runBake(dir, {"bake", mesh.string(), "-o", bad.string(), "--sparse", "--band",
                                    "0.5", "--backend", "gpu", "--quiet"})
                  .code,
              2);
    EXPECT_EQ(clirun::runBake(dir, {"bake", mesh.string(), "-o", bad.string(), "--sparse",
                                    "--storage", "f16", "--backend", "gpu", "--quiet"})
                  .code,
              2);
    EXPECT_FALSE(fs::exists(bad));
}

} // namespace
