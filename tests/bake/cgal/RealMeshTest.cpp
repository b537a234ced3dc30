// Third-party meshes (assimp's and CGAL's test models): import diagnostics and a CGAL bake each.
//
// The expected counts below were measured with assimp 5.2.5 and CGAL 5.5.1 (Debian 12) and
// checked for plausibility: box.fbx is a cube (8 corners, 12 triangles); huesitos.fbx is a
// closed low-poly bone; spider.fbx/obj has open, intersecting legs and 56 zero-area triangles;
// WusonOBJ.obj has open seams (412 boundary edges) and intersecting parts; bunny00.off is a
// closed, clean bunny; elephant-with-holes.off is open with 1353 boundary edges.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "TestMeshes.h"
#include "sluice/bake/cgal/CgalBaker.h"
#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/import/MeshImport.h"

namespace {

using namespace sluice;
using namespace sluice::bake;
namespace fs = std::filesystem;

struct RealMesh {
    const char* path;
    std::uint64_t triangles, vertices, degenerate, boundaryEdges;
    bool closed, selfIntersecting;
    format::SignMethod autoSign;
};

std::ostream& operator<<(std::ostream& out, const RealMesh& mesh) {
    return out << fs::path(mesh.path).filename().string();
}

using format::SignMethod;
const RealMesh kClosedMeshes[] = {
    {SLUICE_ASSIMP_MODELS "/FBX/box.fbx", 12, 8, 0, 0, true, false, SignMethod::Parity},
    {SLUICE_ASSIMP_MODELS "/FBX/huesitos.fbx", 120, 62, 0, 0, true, false, SignMethod::Parity},
    {SLUICE_CGAL_MESHES "/bunny00.off", 75408, 37706, 0, 0, true, false, SignMethod::Parity},
};
const RealMesh kOpenMeshes[] = {
    {SLUICE_ASSIMP_MODELS "/FBX/spider.fbx", 1368, 722, 56, 72, false, true, SignMethod::Winding},
    {SLUICE_ASSIMP_MODELS "/OBJ/WusonOBJ.obj", 3732, 2117, 0, 412, false, true,
     SignMethod::Winding},
    {SLUICE_CGAL_MESHES "/elephant-with-holes.off", 4463, 2733, 0, 1353, false, false,
     SignMethod::Winding},
};

class RealMeshTest : public testing::TestWithParam<RealMesh> {};
class ClosedRealMeshTest : public RealMeshTest {};
class OpenRealMeshTest : public RealMeshTest {};

/// Distance from p to the box (0 inside).
double distanceToBox(const glm::dvec3& p, const Box& box) {
    return glm::length(glm::max(glm::max(box.lo - p, p - box.hi), glm::dvec3(0.0)));
}

TEST_P(RealMeshTest, ImportsWithTheMeasuredDiagnostics) {
    const RealMesh& expected = GetParam();
    Result<ImportedMesh> mesh = importMesh(expected.path, {});
    ASSERT_TRUE(mesh.ok()) << mesh.error().message();
    const format::MeshDiagnostics& d = mesh->diagnostics;
    EXPECT_EQ(d.triangles, expected.triangles);
    EXPECT_EQ(d.vertices, expected.vertices);
    EXPECT_EQ(d.degenerateTriangles, expected.degenerate);
    EXPECT_EQ(d.boundaryEdges, expected.boundaryEdges);
    EXPECT_EQ(d.nonManifoldEdges, 0u);
    EXPECT_EQ(d.closed, expected.closed);
    EXPECT_EQ(d.selfIntersecting, expected.selfIntersecting);
    EXPECT_EQ(mesh->sourceFile, fs::path(expected.path).filename().string());
    EXPECT_EQ(mesh->sourceHash.size(), 16u);
}

TEST_P(RealMeshTest, BakesASensibleFieldThatAgreesWithBruteForce) {
    const RealMesh& expected = GetParam();
    Result<ImportedMesh> mesh = importMesh(expected.path, {});
    ASSERT_TRUE(mesh.ok()) << mesh.error().message();

    const auto start = std::chrono::steady_clock::now();
    Result<format::ColliderAsset> asset = bakeCgal(*mesh, {.grid = {.resolution = 28}});
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    std::printf("  %s: %llu grid points in %.2f s (%s)\n", mesh->sourceFile.c_str(),
                static_cast<unsigned long long>(asset->pointCount()), seconds,
                asset->meta.bake.signUsed == SignMethod::Parity ? "parity" : "winding");
    EXPECT_EQ(asset->meta.bake.signUsed, expected.autoSign);

    const format::ColliderMeta& meta = asset->meta;
    const Box box = mesh->soup.bounds();
    const double diagonal = glm::length(box.hi - box.lo);
    const double storage = 1e-6 * (diagonal + 10 * meta.voxelSize); // float rounding [world units]
    int negative = 0;
    for (float phi : asset->distances) {
        ASSERT_TRUE(std::isfinite(phi));
        negative += phi < 0.0f;
    }
    EXPECT_GT(negative, 0) << "no grid point inside";

    // The grid corners lie padding * sqrt(3) voxels off the mesh box, outside: the distance is
    // at least the distance to the box (the mesh is inside it) and at most that to any vertex.
    for (std::uint32_t c = 0; c < 8; ++c) {
        const std::uint32_t i = (c & 1) ? meta.dims.x - 1 : 0, j = (c & 2) ? meta.dims.y - 1 : 0,
                            k = (c & 4) ? meta.dims.z - 1 : 0;
        const glm::dvec3 p = asset->pointPosition(i, j, k);
        const double phi = asset->distances[asset->index(i, j, k)];
        double nearestVertex = std::numeric_limits<double>::infinity();
        for (const glm::dvec3& v : mesh->soup.positions)
            nearestVertex = std::min(nearestVertex, glm::length(p - v));
        EXPECT_GT(phi, 0.0) << "corner " << c;
        EXPECT_GE(phi, distanceToBox(p, box) - storage) << "corner " << c;
        EXPECT_LE(phi, nearestVertex + storage) << "corner " << c;
    }

    // |phi| against brute force over every triangle, at a spread of grid points.
    const std::uint64_t count = asset->pointCount();
    for (std::uint64_t n = 0; n < 150; ++n) {
        const std::uint64_t index = (n * 7919 * 104729) % count;
        const std::uint32_t i = std::uint32_t(index % meta.dims.x);
        const std::uint32_t j = std::uint32_t(index / meta.dims.x % meta.dims.y);
        const std::uint32_t k = std::uint32_t(index / meta.dims.x / meta.dims.y);
        const double exact =
            testmesh::bruteForceDistance(mesh->soup, asset->pointPosition(i, j, k));
        ASSERT_NEAR(std::abs(asset->distances[index]), exact, storage) << "grid point " << index;
    }
}

TEST_P(ClosedRealMeshTest, GetsTheSameFieldFromParityAndWindingAtEveryGridPoint) {
    const RealMesh& expected = GetParam();
    Result<ImportedMesh> mesh = importMesh(expected.path, {});
    ASSERT_TRUE(mesh.ok()) << mesh.error().message();
    Result<format::ColliderAsset> parity =
        bakeCgal(*mesh, {.grid = {.resolution = 28}, .sign = SignMode::Parity});
    Result<format::ColliderAsset> winding =
        bakeCgal(*mesh, {.grid = {.resolution = 28}, .sign = SignMode::Winding});
    ASSERT_TRUE(parity.ok() && winding.ok());
    ASSERT_EQ(parity->meta.bake.signUsed, SignMethod::Parity);
    ASSERT_EQ(winding->meta.bake.signUsed, SignMethod::Winding);
    for (std::size_t n = 0; n < parity->distances.size(); ++n)
        ASSERT_EQ(parity->distances[n], winding->distances[n]) << "grid point " << n;
}

TEST_P(OpenRealMeshTest, TakesItsSignFromTheBruteForceWindingNumber) {
    const RealMesh& expected = GetParam();
    Result<ImportedMesh> mesh = importMesh(expected.path, {});
    ASSERT_TRUE(mesh.ok()) << mesh.error().message();
    Result<format::ColliderAsset> asset = bakeCgal(*mesh, {.grid = {.resolution = 20}});
    Result<CgalReference> reference =
        CgalReference::build(mesh->soup, mesh->diagnostics, SignMode::Winding);
    ASSERT_TRUE(asset.ok() && reference.ok());
    int compared = 0;
    for (std::uint32_t k = 0; k < asset->meta.dims.z; k += 2)
        for (std::uint32_t j = 0; j < asset->meta.dims.y; j += 2)
            for (std::uint32_t i = 0; i < asset->meta.dims.x; i += 2) {
                const float phi = asset->distances[asset->index(i, j, k)];
                const double w = reference->windingNumber(asset->pointPosition(i, j, k));
                if (phi == 0.0f || std::abs(w - 0.5) < 1e-9)
                    continue;
                ASSERT_EQ(phi<0.0f, w> 0.5) << i << " " << j << " " << k << " w = " << w;
                ++compared;
            }
    EXPECT_GT(compared, 500);
}

std::string meshName(const testing::TestParamInfo<RealMesh>& param) {
    std::string name = fs::path(param.param.path).stem().string();
    std::replace_if(
        name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
    return name;
}

INSTANTIATE_TEST_SUITE_P(Closed, RealMeshTest, testing::ValuesIn(kClosedMeshes), meshName);
INSTANTIATE_TEST_SUITE_P(Open, RealMeshTest, testing::ValuesIn(kOpenMeshes), meshName);
INSTANTIATE_TEST_SUITE_P(Models, ClosedRealMeshTest, testing::ValuesIn(kClosedMeshes), meshName);
INSTANTIATE_TEST_SUITE_P(Models, OpenRealMeshTest, testing::ValuesIn(kOpenMeshes), meshName);

TEST(RealMesh, SpiderReadsTheSameFromFbxAndObj) {
    // spider.fbx holds the spider of spider.obj, 100 times larger (measured); scaled back by
    // the import option, the two agree.
    Result<ImportedMesh> fbx = importMesh(SLUICE_ASSIMP_MODELS "/FBX/spider.fbx", {.scale = 0.01});
    Result<ImportedMesh> obj = importMesh(SLUICE_ASSIMP_MODELS "/OBJ/spider.obj", {});
    ASSERT_TRUE(fbx.ok() && obj.ok());
    EXPECT_EQ(fbx->diagnostics.triangles, obj->diagnostics.triangles);
    EXPECT_EQ(fbx->diagnostics.vertices, obj->diagnostics.vertices);
    const Box a = fbx->soup.bounds(), b = obj->soup.bounds();
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(a.lo[axis], b.lo[axis], 1e-3 * (b.hi[axis] - b.lo[axis]));
        EXPECT_NEAR(a.hi[axis], b.hi[axis], 1e-3 * (b.hi[axis] - b.lo[axis]));
    }
}

} // namespace
