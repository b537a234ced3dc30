// The GPU baker against the CGAL reference at every grid point, on analytic and real meshes.
//
// Limits: max |phi - phi_ref| <= 1e-3 voxel wherever the signs agree; no sign
// mismatch on closed meshes; on open or self-intersecting ones (reference: the exact generalized
// winding number) at most 0.1 % mismatches, none farther than 1 voxel from the surface.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../gpu/GpuTest.h"
#include "TestMeshes.h"
#include "sluice/bake/cgal/CgalBaker.h"
#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/gpu/GpuBaker.h"
#include "sluice/format/asset/AssetIO.h"

namespace {

using namespace sluice;
using namespace sluice::bake;
namespace fs = std::filesystem;

constexpr double kMaxErrorVoxels = 1e-3;
constexpr double kMaxSignMismatchShare = 1e-3;
constexpr double kMismatchBandVoxels = 1.0;

struct BakeCase {
    std::string name;
    std::function<Result<ImportedMesh>()> load;
    std::uint32_t resolution;
    SignMode sign = SignMode::Auto;
    bool exactSign = true; ///< closed: no mismatch allowed
};

std::ostream& operator<<(std::ostream& out, const BakeCase& c) {
    return out << c.name;
}

std::function<Result<ImportedMesh>()> analytic(std::function<TriangleSoup()> make,
                                               std::string name) {
    return [make, name]() -> Result<ImportedMesh> { return testmesh::imported(make(), name); };
}

std::function<Result<ImportedMesh>()> file(std::string path) {
    return [path]() { return importMesh(path, {}); };
}

/// What comparing a GPU bake with the reference found.
struct Comparison {
    std::uint64_t points = 0;
    double maxErrorVoxels = 0.0;    ///< max |phi - phi_ref| where the signs agree
    double maxAbsErrorVoxels = 0.0; ///< max ||phi| - |phi_ref|| everywhere
    std::uint64_t signMismatches = 0;
    double farthestMismatchVoxels = 0.0; ///< max |phi_ref| over mismatches
    std::uint64_t ties = 0; ///< opposite signs where the winding number is 0.5: either is right
};

/// Where the exact winding number is this close to 0.5 (grid points on the plane of a hole of a
/// symmetric mesh, e.g. the rim disc of a hemisphere), the sign is a tie.
constexpr double kTieBand = 1e-6;

Comparison compare(const format::ColliderAsset& asset, const CgalReference& reference) {
    const format::ColliderMeta& meta = asset.meta;
    std::vector<glm::dvec3> points;
    points.reserve(asset.pointCount());
    for (std::uint32_t k = 0; k < meta.dims.z; ++k)
        for (std::uint32_t j = 0; j < meta.dims.y; ++j)
            for (std::uint32_t i = 0; i < meta.dims.x; ++i)
                points.push_back(asset.pointPosition(i, j, k));
    const std::vector<double> exact = reference.signedDistances(points);
    Comparison c;
    c.points = points.size();
    for (std::size_t n = 0; n < exact.size(); ++n) {
        const double phi = asset.distances[n], ref = exact[n];
        const double absError = std::abs(std::abs(phi) - std::abs(ref)) / meta.voxelSize;
        c.maxAbsErrorVoxels = std::max(c.maxAbsErrorVoxels, absError);
        if (phi != 0.0 && ref != 0.0 && (phi < 0.0) != (ref < 0.0)) {
            if (reference.signMethod() == format::SignMethod::Winding &&
                std::abs(reference.windingNumber(points[n]) - 0.5) < kTieBand) {
                ++c.ties;
                continue;
            }
            ++c.signMismatches;
            c.farthestMismatchVoxels =
                std::max(c.farthestMismatchVoxels, std::abs(ref) / meta.voxelSize);
        } else {
            c.maxErrorVoxels = std::max(c.maxErrorVoxels, std::abs(phi - ref) / meta.voxelSize);
        }
    }
    return c;
}

class GpuBakerTest : public gpu::test::GpuTest {};
class GpuBakerMeshTest : public GpuBakerTest, public testing::WithParamInterface<BakeCase> {};

TEST_P(GpuBakerMeshTest, MatchesTheCgalReferenceAtEveryGridPoint) {
    const BakeCase& c = GetParam();
    Result<ImportedMesh> mesh = c.load();
    ASSERT_TRUE(mesh.ok()) << mesh.error().message();
    const BakeSettings settings{.grid = {.resolution = c.resolution}, .sign = c.sign};
    GpuBakeStats stats;
    Result<format::ColliderAsset> asset =
        bakeGpu(*mesh, settings, context(), nullptr, {.profile = true}, &stats);
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    Result<CgalReference> reference = CgalReference::build(mesh->soup, mesh->diagnostics, c.sign);
    ASSERT_TRUE(reference.ok()) << reference.error().message();
    Result<format::ColliderAsset> cgal = bakeCgal(*mesh, settings);
    ASSERT_TRUE(cgal.ok());

    // Same grid and provenance as the CGAL path, backend aside.
    EXPECT_EQ(asset->meta.bake.backend, "gpu");
    EXPECT_EQ(asset->meta.dims, cgal->meta.dims);
    EXPECT_EQ(asset->meta.origin, cgal->meta.origin);
    EXPECT_EQ(asset->meta.voxelSize, cgal->meta.voxelSize);
    EXPECT_EQ(asset->meta.bake.signUsed, reference->signMethod());
    EXPECT_EQ(asset->meta.bake.signMode, cgal->meta.bake.signMode);
    EXPECT_EQ(asset->meta.sourceHash, cgal->meta.sourceHash);
    ASSERT_EQ(asset->meta.meshMass.has_value(), cgal->meta.meshMass.has_value());
    if (asset->meta.meshMass) {
        EXPECT_EQ(asset->meta.meshMass->volume, cgal->meta.meshMass->volume);
        EXPECT_EQ(asset->meta.meshMass->centerOfMass, cgal->meta.meshMass->centerOfMass);
        EXPECT_EQ(asset->meta.meshMass->inertia, cgal->meta.meshMass->inertia);
    }
    EXPECT_EQ(asset->meta.meshMass.has_value(), c.exactSign) << "closed meshes, and only they";

    const Comparison r = compare(*asset, *reference);
    std::printf(
        "  %-28s %3u^ res, %7llu points, %5llu triangles: max error %.2e voxel, "
        "%llu sign mismatches (farthest %.3f voxel, %llu ties); distance %.1f ms, sign %.1f ms\n",
        c.name.c_str(), c.resolution, static_cast<unsigned long long>(r.points),
        static_cast<unsigned long long>(stats.triangles), r.maxErrorVoxels,
        static_cast<unsigned long long>(r.signMismatches), r.farthestMismatchVoxels,
        static_cast<unsigned long long>(r.ties), stats.distanceNs * 1e-6, stats.signNs * 1e-6);
    EXPECT_LE(r.maxErrorVoxels, kMaxErrorVoxels);
    EXPECT_LE(r.maxAbsErrorVoxels, kMaxErrorVoxels);
    if (c.exactSign) {
        EXPECT_EQ(r.signMismatches, 0u);
    } else {
        EXPECT_LE(double(r.signMismatches), kMaxSignMismatchShare * double(r.points));
        EXPECT_LE(r.farthestMismatchVoxels, kMismatchBandVoxels);
    }
    std::uint64_t inside = 0;
    for (float phi : asset->distances)
        inside += phi < 0.0f;
    EXPECT_GT(inside, 0u) << "no grid point inside";
}

const glm::dvec3 kCenter{0.3, -0.2, 0.1};

const BakeCase kCases[] = {
    {"box",
     analytic(
         [] {
             return testmesh::boxSoup({-1, -0.5, -0.25}, {1, 0.5, 0.75});
         },
         "box"),
     32},
    {"box_winding",
     analytic(
         [] {
             return testmesh::boxSoup({-1, -0.5, -0.25}, {1, 0.5, 0.75});
         },
         "box"),
     24, SignMode::Winding},
    {"icosphere_parity", analytic([] { return testmesh::icoSphereSoup(kCenter, 1.0, 3); }, "ico"),
     32, SignMode::Parity},
    {"icosphere_winding", analytic([] { return testmesh::icoSphereSoup(kCenter, 1.0, 3); }, "ico"),
     32, SignMode::Winding},
    {"torus", analytic([] { return testmesh::torusSoup(kCenter, 1.0, 0.35, 48, 20); }, "torus"),
     40},
    {"open_box",
     analytic(
         [] {
             return testmesh::boxSoup({-1, -0.5, -0.25}, {1, 0.5, 0.75}, true);
         },
         "open"),
     24, SignMode::Auto, false},
    {"hemisphere",
     analytic([] { return testmesh::uvSphereSoup(kCenter, 1.0, 32, 16, true); }, "hemi"), 24,
     SignMode::Auto, false},
    {"box_fbx", file(SLUICE_ASSIMP_MODELS "/FBX/box.fbx"), 32},
    {"huesitos_fbx", file(SLUICE_ASSIMP_MODELS "/FBX/huesitos.fbx"), 40},
    {"spider_fbx", file(SLUICE_ASSIMP_MODELS "/FBX/spider.fbx"), 40, SignMode::Auto, false},
    {"wuson_obj", file(SLUICE_ASSIMP_MODELS "/OBJ/WusonOBJ.obj"), 40, SignMode::Auto, false},
    {"elephant_with_holes_off", file(SLUICE_CGAL_MESHES "/elephant-with-holes.off"), 40,
     SignMode::Auto, false},
};

INSTANTIATE_TEST_SUITE_P(Meshes, GpuBakerMeshTest, testing::ValuesIn(kCases),
                         [](const testing::TestParamInfo<BakeCase>& param) {
                             return param.param.name;
                         });

TEST_F(GpuBakerTest, BakingTwiceGivesIdenticalBytes) {
    Result<ImportedMesh> mesh = importMesh(SLUICE_ASSIMP_MODELS "/OBJ/WusonOBJ.obj", {});
    ASSERT_TRUE(mesh.ok()) << mesh.error().message();
    const BakeSettings settings{.grid = {.resolution = 24}};
    Result<format::ColliderAsset> first = bakeGpu(*mesh, settings, context());
    // A different dispatch split must not change a bit either.
    Result<format::ColliderAsset> second =
        bakeGpu(*mesh, settings, context(), nullptr, {.maxGroupsPerDispatch = 7});
    ASSERT_TRUE(first.ok() && second.ok());
    Result<format::EncodedAsset> a = format::encodeAsset(*first);
    Result<format::EncodedAsset> b = format::encodeAsset(*second);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_TRUE(a->bytes == b->bytes);
}

TEST_F(GpuBakerTest, FarFieldWindingNumberGivesTheSameSignsAsTheExactSum) {
    // beta = 1e30 makes no node far: every triangle's solid angle is summed at every point.
    for (const char* path :
         {SLUICE_ASSIMP_MODELS "/OBJ/WusonOBJ.obj", SLUICE_ASSIMP_MODELS "/FBX/huesitos.fbx"}) {
        Result<ImportedMesh> mesh = importMesh(path, {});
        ASSERT_TRUE(mesh.ok()) << mesh.error().message();
        const BakeSettings settings{.grid = {.resolution = 24}, .sign = SignMode::Winding};
        GpuBakeStats fast, exact;
        Result<format::ColliderAsset> a =
            bakeGpu(*mesh, settings, context(), nullptr, {.profile = true}, &fast);
        Result<format::ColliderAsset> b =
            bakeGpu(*mesh, settings, context(), nullptr, {.beta = 1e30, .profile = true}, &exact);
        ASSERT_TRUE(a.ok() && b.ok());
        EXPECT_TRUE(a->distances == b->distances) << path;
        std::printf("  %s: sign pass %.1f ms with the far field, %.1f ms exact\n",
                    mesh->sourceFile.c_str(), fast.signNs * 1e-6, exact.signNs * 1e-6);
    }
}

TEST_F(GpuBakerTest, BakesAGridOfManySlabsExactly) {
    // About 4.6M grid points: the fine pass runs in many slabs, each with its own pending list.
    // Checked against the reference on a seeded sample of points, half of them near the surface.
    const ImportedMesh mesh = testmesh::imported(testmesh::icoSphereSoup(kCenter, 1.0, 3), "ico");
    const BakeSettings settings{.grid = {.resolution = 160}};
    GpuBakeStats stats;
    Result<format::ColliderAsset> asset =
        bakeGpu(mesh, settings, context(), nullptr, {.profile = true}, &stats);
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    Result<CgalReference> reference = CgalReference::build(mesh.soup, mesh.diagnostics, {});
    ASSERT_TRUE(reference.ok()) << reference.error().message();
    const format::ColliderMeta& meta = asset->meta;
    std::mt19937 random(7);
    std::vector<std::array<std::uint32_t, 3>> picks;
    while (picks.size() < 20000) {
        const std::array<std::uint32_t, 3> ijk{std::uint32_t(random() % meta.dims.x),
                                               std::uint32_t(random() % meta.dims.y),
                                               std::uint32_t(random() % meta.dims.z)};
        const double phi =
            asset->distances[ijk[0] + meta.dims.x * (ijk[1] + std::size_t(meta.dims.y) * ijk[2])];
        if (picks.size() % 2 == 0 || std::abs(phi) < 3.0 * meta.voxelSize)
            picks.push_back(ijk);
    }
    double maxError = 0.0;
    std::uint64_t mismatches = 0;
    for (const auto& [i, j, k] : picks) {
        const double phi = asset->distances[i + meta.dims.x * (j + std::size_t(meta.dims.y) * k)];
        const double ref = reference->signedDistance(asset->pointPosition(i, j, k));
        mismatches += phi != 0.0 && ref != 0.0 && (phi < 0.0) != (ref < 0.0);
        maxError = std::max(maxError, std::abs(phi - ref) / meta.voxelSize);
    }
    std::printf("  %llu points, %llu dispatches, %llu pending: max error %.2e voxel on %zu\n",
                static_cast<unsigned long long>(asset->pointCount()),
                static_cast<unsigned long long>(stats.dispatches),
                static_cast<unsigned long long>(stats.pendingPoints), maxError, picks.size());
    EXPECT_GT(asset->pointCount(), 4u * (std::uint64_t(1) << 20));
    EXPECT_LE(maxError, kMaxErrorVoxels);
    EXPECT_EQ(mismatches, 0u);
}

TEST_F(GpuBakerTest, ComputesTheWindingNumberOnlyWhereNoEmptyBallDecidesTheSign) {
    // Closed: the coarse points' empty balls sign most points. Open: every point is computed.
    const ImportedMesh closed =
        testmesh::imported(testmesh::torusSoup(kCenter, 1.0, 0.35, 48, 20), "torus");
    const ImportedMesh open =
        testmesh::imported(testmesh::boxSoup({-1, -0.5, -0.25}, {1, 0.5, 0.75}, true), "open");
    const BakeSettings settings{.grid = {.resolution = 48}};
    GpuBakeStats closedStats, openStats;
    Result<format::ColliderAsset> a =
        bakeGpu(closed, settings, context(), nullptr, {}, &closedStats);
    Result<format::ColliderAsset> b = bakeGpu(open, settings, context(), nullptr, {}, &openStats);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_GT(closedStats.pendingPoints, 0u);
    EXPECT_LT(double(closedStats.pendingPoints), 0.25 * double(a->pointCount()));
    std::uint64_t offSurface = 0;
    for (float phi : b->distances)
        offSurface += phi != 0.0f;
    EXPECT_EQ(openStats.pendingPoints, offSurface);
}

TEST_F(GpuBakerTest, StoresHalfFloatsWithTheirMeasuredQuantizationError) {
    const ImportedMesh mesh = testmesh::imported(testmesh::icoSphereSoup(kCenter, 1.0, 2), "ico");
    Result<format::ColliderAsset> asset =
        bakeGpu(mesh, {.grid = {.resolution = 24}, .storage = format::Storage::F16}, context());
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    EXPECT_EQ(asset->meta.storage, format::Storage::F16);
    Result<format::EncodedAsset> encoded = format::encodeAsset(*asset);
    ASSERT_TRUE(encoded.ok());
    float largest = 0.0f;
    for (float phi : asset->distances)
        largest = std::max(largest, std::abs(phi));
    EXPECT_GT(encoded->quantizationError, 0.0);
    EXPECT_LE(encoded->quantizationError, largest * std::ldexp(1.0, -11) * 1.01);
}

TEST_F(GpuBakerTest, RejectsAGridOverTheLargestGpuBufferCleanly) {
    const ImportedMesh mesh = testmesh::imported(testmesh::icoSphereSoup(kCenter, 1.0, 1), "ico");
    Result<format::ColliderAsset> asset = bakeGpu(mesh, {.grid = {.resolution = 64}}, context(),
                                                  nullptr, {.maxBufferBytes = 1 << 20});
    ASSERT_FALSE(asset.ok());
    EXPECT_EQ(asset.error().code, ErrorCode::SizeOverflow);
    EXPECT_NE(asset.error().detail.find("coarser resolution"), std::string::npos)
        << asset.error().detail;
}

TEST_F(GpuBakerTest, RejectsAGridOverTheBakeLimitBeforeTouchingTheGpu) {
    const ImportedMesh mesh = testmesh::imported(testmesh::icoSphereSoup(kCenter, 1.0, 1), "ico");
    Result<format::ColliderAsset> asset = bakeGpu(mesh, {.grid = {.voxelSize = 1e-4}}, context());
    ASSERT_FALSE(asset.ok());
    EXPECT_EQ(asset.error().code, ErrorCode::SizeOverflow);
}

TEST_F(GpuBakerTest, RefusesParityOnAnOpenMesh) {
    const ImportedMesh mesh =
        testmesh::imported(testmesh::boxSoup({-1, -1, -1}, {1, 1, 1}, true), "open");
    Result<format::ColliderAsset> asset =
        bakeGpu(mesh, {.grid = {.resolution = 8}, .sign = SignMode::Parity}, context());
    ASSERT_FALSE(asset.ok());
    EXPECT_EQ(asset.error().code, ErrorCode::InvalidArgument);
}

} // namespace
