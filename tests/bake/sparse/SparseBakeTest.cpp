// Sparse bakes: band accuracy against CGAL, signs deep inside, NanoVDB and OpenVDB round trips,
// validate on sparse assets, and hostile sparse inputs on the command line.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "interop/VdbHeaders.h"
SLUICE_VDB_WARNINGS_OFF
#include <nanovdb/NanoVDB.h>
SLUICE_VDB_WARNINGS_ON

#include "CliRun.h"
#include "TestMeshes.h"
#include "sluice/bake/cgal/CgalBaker.h"
#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/cgal/CgalSparseBaker.h"
#include "sluice/bake/interop/NanoVdbIO.h"
#include "sluice/bake/sparse/SparseBaker.h"
#include "sluice/bake/validate/Validate.h"
#include "sluice/bake/interop/VdbIO.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/NanoVdbCheck.h"
#include "sluice/format/asset/SdfSampler.h"

namespace fs = std::filesystem;
using namespace sluice;

namespace {

const glm::dvec3 kCentre{0.013, -0.021, 0.007};
constexpr double kRadius = 0.5;

bake::ImportedMesh sphereMesh() {
    return testmesh::imported(testmesh::icoSphereSoup(kCentre, kRadius, 3), "sphere.obj");
}

bake::BakeSettings settingsAt(std::uint32_t resolution, double padding = 4.0) {
    bake::BakeSettings s;
    s.grid.resolution = resolution;
    s.grid.padding = padding;
    return s;
}

format::ColliderAsset bakeSparse(const bake::ImportedMesh& mesh, std::uint32_t resolution,
                                 double band = 3.0, bake::SparseBakeStats* stats = nullptr) {
    auto r = bake::bakeSparseCgal(mesh, settingsAt(resolution), {.band = band}, false, stats);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message());
    return r.ok() ? std::move(*r) : format::ColliderAsset{};
}

const nanovdb::NanoTree<float>& treeOf(const format::ColliderAsset& a) {
    return reinterpret_cast<const nanovdb::NanoGrid<float>*>(a.grid.data())->tree();
}

std::vector<nanovdb::Coord> activeVoxels(const format::ColliderAsset& a) {
    std::vector<nanovdb::Coord> out;
    const auto& tree = treeOf(a);
    const auto* leaf = tree.getFirstNode<0>();
    for (std::uint32_t n = 0; n < tree.nodeCount(0); ++n, ++leaf)
        for (auto it = leaf->beginValueOn(); it; ++it)
            out.push_back(it.getCoord());
    return out;
}

} // namespace

TEST(SparseBake, BandVoxelsHoldTheExactCgalDistance) {
    const bake::ImportedMesh mesh = sphereMesh();
    bake::SparseBakeStats stats;
    const format::ColliderAsset a = bakeSparse(mesh, 48, 3.0, &stats);
    ASSERT_TRUE(a.sparse());
    auto ref = bake::CgalReference::build(mesh.soup, mesh.diagnostics, bake::SignMode::Auto);
    ASSERT_TRUE(ref.ok());
    const double h = a.meta.voxelSize;
    const auto voxels = activeVoxels(a);
    ASSERT_GT(voxels.size(), 5000u);
    EXPECT_EQ(voxels.size(), stats.activeVoxels);
    double maxError = 0.0;
    for (const nanovdb::Coord& c : voxels) {
        const glm::dvec3 p = a.pointPosition(c[0], c[1], c[2]);
        const double exact = ref->signedDistance(p);
        const float stored = treeOf(a).getValue(c);
        EXPECT_LT(std::abs(stored), 3.0 * h + 1e-7) << "active voxels lie in the band";
        maxError = std::max(maxError, std::abs(stored - exact) / h);
    }
    EXPECT_LE(maxError, 1e-3) << "max error in the band [voxels]";
    EXPECT_GT(stats.uniformBlocks, 0u);
}

TEST(SparseBake, WorkGrowsWithTheSurfaceNotTheVolume) {
    const bake::ImportedMesh mesh = sphereMesh();
    bake::SparseBakeStats coarse, fine;
    const format::ColliderAsset a = bakeSparse(mesh, 48, 3.0, &coarse);
    const format::ColliderAsset b = bakeSparse(mesh, 96, 3.0, &fine);
    EXPECT_LT(fine.voxelsComputed, b.pointCount() / 2);
    // Twice the resolution: about 4x the band (surface), not 8x (volume).
    const double work = double(fine.voxelsComputed) / double(coarse.voxelsComputed);
    const double band = double(fine.activeVoxels) / double(coarse.activeVoxels);
    EXPECT_GT(work, 3.0);
    EXPECT_LT(work, 5.5);
    EXPECT_GT(band, 3.5);
    EXPECT_LT(band, 4.5);
    EXPECT_LT(double(b.grid.size()) / double(a.grid.size()), 5.5);
}

TEST(SparseBake, EqualsTheDenseBakeInTheBandAndHasItsSignEverywhere) {
    const bake::ImportedMesh mesh = sphereMesh();
    const format::ColliderAsset sparse = bakeSparse(mesh, 40);
    auto dense = bake::bakeCgal(mesh, settingsAt(40));
    ASSERT_TRUE(dense.ok());
    ASSERT_EQ(dense->meta.dims, sparse.meta.dims) << "same grid (padding 4 covers band 3)";
    ASSERT_EQ(dense->meta.origin, sparse.meta.origin);
    const auto& tree = treeOf(sparse);
    std::uint64_t signErrors = 0, bandPoints = 0;
    for (std::uint32_t k = 0; k < dense->meta.dims.z; ++k)
        for (std::uint32_t j = 0; j < dense->meta.dims.y; ++j)
            for (std::uint32_t i = 0; i < dense->meta.dims.x; ++i) {
                const nanovdb::Coord c{int(i), int(j), int(k)};
                const float d = dense->distances[dense->index(i, j, k)];
                const float s = tree.getValue(c);
                if (tree.isActive(c)) {
                    ++bandPoints;
                    ASSERT_EQ(s, d) << "at " << i << " " << j << " " << k;
                } else if (std::signbit(s) != std::signbit(d)) {
                    ++signErrors;
                }
            }
    EXPECT_GT(bandPoints, 1000u);
    EXPECT_EQ(signErrors, 0u);
}

TEST(SparseBake, DeepInsideIsNegativeAndPushesOut) {
    const format::ColliderAsset a = bakeSparse(sphereMesh(), 64);
    const format::SdfSampler s(a);
    const double band = 3.0 * a.meta.voxelSize;
    EXPECT_FLOAT_EQ(s.value(kCentre), float(-band));
    EXPECT_FLOAT_EQ(s.value(kCentre + glm::dvec3(0.2, -0.1, 0.1)), float(-band));
    EXPECT_GT(s.value(kCentre + glm::dvec3(0.0, 0.0, 0.6)), 0.0f);
    // Near the surface the gradient points outward.
    for (const glm::dvec3 dir :
         {glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0.6, 0, 0.8)}) {
        const glm::dvec3 p = kCentre + dir * (kRadius - 0.5 * a.meta.voxelSize);
        EXPECT_LT(s.value(p), 0.0f);
        EXPECT_GT(glm::dot(glm::normalize(s.gradient(p)), dir), 0.95);
    }
}

TEST(SparseBake, BakingTwiceGivesIdenticalBytes) {
    const bake::ImportedMesh mesh = sphereMesh();
    auto a = format::encodeAsset(bakeSparse(mesh, 32));
    auto b = format::encodeAsset(bakeSparse(mesh, 32));
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->bytes, b->bytes);
}

TEST(SparseBake, ValidateChecksTheBandAndTheTileSigns) {
    const bake::ImportedMesh mesh = sphereMesh();
    const format::ColliderAsset a = bakeSparse(mesh, 40);
    bake::ValidateOptions options;
    options.samplePoints = 20000;
    auto report = bake::validate(a, mesh, options);
    ASSERT_TRUE(report.ok()) << report.error().message();
    EXPECT_LE(report->figures.maxError, 1e-3);
    EXPECT_EQ(report->figures.signMismatches, 0u);
    EXPECT_GT(report->bandPoints, 5000u);
    EXPECT_GT(report->tilePoints, 5000u);
    EXPECT_NEAR(report->figures.eikonalMedian, 1.0, 0.05);

    // Tiles with the wrong sign are found.
    format::ColliderAsset flipped = a;
    auto* grid = reinterpret_cast<nanovdb::NanoGrid<float>*>(flipped.grid.data());
    const float bg = grid->tree().root().data()->mBackground;
    auto* lower = grid->tree().getFirstNode<1>();
    std::uint64_t changed = 0;
    for (std::uint32_t n = 0; n < 4096; ++n)
        if (!lower->data()->mChildMask.isOn(n) && lower->data()->mTable[n].value > 0.0f) {
            lower->data()->mTable[n].value = -bg; // outside tiles now read inside
            ++changed;
        }
    ASSERT_GT(changed, 0u);
    options.samplePoints = 4000;
    auto bad = bake::validate(flipped, mesh, options);
    ASSERT_TRUE(bad.ok());
    EXPECT_GT(bad->figures.signMismatches, 0u);
}

TEST(SparseBake, NvdbAndVdbRoundTripsKeepTheGrid) {
    const fs::path dir = testmesh::tempDir("sparse-roundtrip");
    const format::ColliderAsset a = bakeSparse(sphereMesh(), 32);
    ASSERT_TRUE(bake::exportNvdb(a, dir / "s.nvdb").ok());
    auto grid = bake::readNvdbGrid(dir / "s.nvdb");
    ASSERT_TRUE(grid.ok()) << grid.error().message();
    ASSERT_EQ(grid->size(), a.grid.size());
    EXPECT_EQ(std::memcmp(grid->data(), a.grid.data(), a.grid.size()), 0);

    // .vdb: the same values at every grid point of the domain, band voxels active.
    ASSERT_TRUE(bake::exportVdb(a, dir / "s.vdb").ok());
    openvdb::initialize();
    openvdb::io::File file((dir / "s.vdb").string());
    file.open();
    auto vdb = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("sdf"));
    file.close();
    ASSERT_TRUE(vdb);
    EXPECT_EQ(vdb->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_EQ(vdb->activeVoxelCount(), treeOf(a).activeVoxelCount());
    const auto acc = vdb->getConstAccessor();
    for (std::uint32_t k = 0; k < a.meta.dims.z; k += 3)
        for (std::uint32_t j = 0; j < a.meta.dims.y; j += 2)
            for (std::uint32_t i = 0; i < a.meta.dims.x; ++i) {
                const nanovdb::Coord c{int(i), int(j), int(k)};
                ASSERT_EQ(acc.getValue(openvdb::Coord(int(i), int(j), int(k))),
                          treeOf(a).getValue(c));
            }
    // And .vdb / .nvdb bake back to the same surface.
    auto fromNvdb = bake::importNvdbLevelSet(dir / "s.nvdb");
    ASSERT_TRUE(fromNvdb.ok()) << fromNvdb.error().message();
    EXPECT_TRUE(fromNvdb->diagnostics.closed);
    const auto box = fromNvdb->soup.bounds();
    EXPECT_NEAR(box.hi.x - box.lo.x, 2.0 * kRadius, 2.0 * a.meta.voxelSize);
}

TEST(SparseBake, NanoVdbValidateAcceptsTheExportedFile) {
    const fs::path tool = "/usr/bin/nanovdb_validate";
    if (!fs::exists(tool))
        GTEST_SKIP() << "nanovdb_validate not installed (libnanovdb-tools)";
    const fs::path dir = testmesh::tempDir("sparse-nanovdb-validate");
    ASSERT_TRUE(bake::exportNvdb(bakeSparse(sphereMesh(), 24), dir / "s.nvdb").ok());
    const std::string command = tool.string() + " -v " + (dir / "s.nvdb").string() + " >" +
                                (dir / "out.txt").string() + " 2>&1";
    const int status = std::system(command.c_str());
    const std::string out = bake::clirun::readText(dir / "out.txt");
    EXPECT_EQ(status, 0) << out;
    EXPECT_EQ(out.find("rror"), std::string::npos) << out;
}

TEST(SparseBake, TheCommandLineBakesInfoExportsAndRejectsHostileGridsWithExit2) {
    const fs::path dir = testmesh::tempDir("sparse-cli");
    const fs::path obj = dir / "sphere.obj";
    ASSERT_TRUE(testmesh::writeObj(sphereMesh().soup, obj));
    using bake::clirun::runBake;
    using bake::clirun::shown;
    auto run = runBake(dir, {"bake", obj.string(), "-o", (dir / "s.slc").string(), "--sparse",
                             "--band", "3", "--resolution", "32", "--backend", "cgal", "--quiet"});
    ASSERT_EQ(run.code, 0) << shown(run);
    run = runBake(dir, {"info", (dir / "s.slc").string()});
    ASSERT_EQ(run.code, 0) << shown(run);
    EXPECT_NE(run.out.find("layout        sparse"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("leaf node"), std::string::npos) << run.out;
    run = runBake(dir, {"info", (dir / "s.slc").string(), "--slice", "z=0.5", "--png",
                        (dir / "s.png").string()});
    EXPECT_EQ(run.code, 0) << shown(run);
    EXPECT_TRUE(fs::exists(dir / "s.png"));
    run = runBake(dir, {"export", (dir / "s.slc").string(), (dir / "s.nvdb").string()});
    ASSERT_EQ(run.code, 0) << shown(run);
    run = runBake(dir, {"info", (dir / "s.nvdb").string()});
    EXPECT_EQ(run.code, 0) << shown(run);
    run = runBake(dir, {"bake", (dir / "s.nvdb").string(), "-o", (dir / "again.slc").string(),
                        "--resolution", "16", "--backend", "cgal", "--quiet"});
    EXPECT_EQ(run.code, 0) << shown(run);
    run = runBake(dir, {"validate", (dir / "s.slc").string(), obj.string(), "--samples", "4000"});
    EXPECT_EQ(run.code, 0) << shown(run);
    run = runBake(dir, {"bake", obj.string(), "-o", (dir / "x.slc").string(), "--sparse",
                        "--storage", "f16"});
    EXPECT_EQ(run.code, 2) << shown(run);
    run = runBake(dir, {"bake", obj.string(), "-o", (dir / "x.slc").string(), "--band", "2"});
    EXPECT_EQ(run.code, 2) << shown(run);
    run = runBake(
        dir, {"bake", obj.string(), "-o", (dir / "x.slc").string(), "--sparse", "--band", "0.5"});
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_FALSE(fs::exists(dir / "x.slc"));

    // Hostile: a huge leaf count inside a valid container, and a truncated .nvdb.
    auto asset = format::readAsset(dir / "s.slc");
    ASSERT_TRUE(asset.ok());
    std::ifstream in(dir / "s.nvdb", std::ios::binary);
    std::string nvdb{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    {
        std::ofstream out(dir / "cut.nvdb", std::ios::binary);
        out.write(nvdb.data(), std::streamsize(nvdb.size() - 100));
    }
    const std::size_t gridAt = nvdb.size() - asset->grid.size();
    const std::uint32_t huge = 0xFFFFFFFFu;
    std::memcpy(nvdb.data() + gridAt + 672 + 32, &huge, 4);
    {
        std::ofstream out(dir / "huge.nvdb", std::ios::binary);
        out.write(nvdb.data(), std::streamsize(nvdb.size()));
    }
    for (const char* name : {"cut.nvdb", "huge.nvdb"}) {
        run = runBake(dir, {"info", (dir / name).string()});
        EXPECT_EQ(run.code, 2) << name << ": " << shown(run);
        run = runBake(dir, {"bake", (dir / name).string(), "-o", (dir / "y.slc").string()});
        EXPECT_EQ(run.code, 2) << name << ": " << shown(run);
    }
    EXPECT_FALSE(fs::exists(dir / "y.slc"));
}
