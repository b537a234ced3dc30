// The mass properties a bake stores (exact, from the mesh) against those integrated from its
// own distance field (format::massPropertiesFromField), and which bakes store them at all.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <gtest/gtest.h>

#include "TestMeshes.h"
#include "sluice/bake/jobs/BakeJob.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/MassProperties.h"

namespace {

using namespace sluice;
using namespace sluice::bake;
namespace fs = std::filesystem;

/// The bake the field test uses: CGAL (exact, CPU only), 64 voxels along the longest side.
format::ColliderAsset bakeAt64(const ImportedMesh& mesh) {
    BakeRequest request;
    request.backend = "cgal";
    request.resolution = 64;
    Result<BakeOutcome> outcome = bakeMesh(mesh, request);
    EXPECT_TRUE(outcome.ok()) << outcome.error().message();
    return outcome.ok() ? std::move(outcome->asset) : format::ColliderAsset{};
}

/// Bakes `mesh` and expects the stored mesh mass to agree with the field's integral: volume
/// within 1 %, centre of mass within half a voxel, inertia within 2 % (Frobenius norm of the
/// difference over that of the exact tensor). Prints the measured figures.
void expectFieldAgrees(const ImportedMesh& mesh, const std::string& name) {
    ASSERT_TRUE(mesh.diagnostics.closed) << name;
    const format::ColliderAsset asset = bakeAt64(mesh);
    ASSERT_TRUE(asset.meta.meshMass.has_value()) << name << ": a closed mesh gets meshMass";
    const format::MassProperties& exact = *asset.meta.meshMass;
    Result<format::MassProperties> field = format::massPropertiesFromField(asset);
    ASSERT_TRUE(field.ok()) << field.error().message();

    const double volumeDifference = (field->volume - exact.volume) / exact.volume; // signed
    const double volumeError = std::abs(volumeDifference);
    const double comError =
        glm::length(field->centerOfMass - exact.centerOfMass) / asset.meta.voxelSize;
    const double inertiaError =
        testmesh::frobenius(field->inertia - exact.inertia) / testmesh::frobenius(exact.inertia);
    std::printf("  %s (%ux%ux%u): field - mesh volume %+.3f %%, centre of mass %.3f voxels, "
                "inertia %.3f %%\n",
                name.c_str(), asset.meta.dims.x, asset.meta.dims.y, asset.meta.dims.z,
                100.0 * volumeDifference, comError, 100.0 * inertiaError);
    EXPECT_LE(volumeError, 0.01) << name;
    EXPECT_LE(comError, 0.5) << name;
    EXPECT_LE(inertiaError, 0.02) << name;
}

TEST(MeshMassField, ABoxAgreesWithItsFieldIntegral) {
    // Rotated, so the inertia tensor has off-diagonal terms the field must reproduce.
    TriangleSoup box = testmesh::boxSoup({-0.6, -0.25, -0.4}, {0.6, 0.25, 0.4});
    const glm::dmat3 rotation(
        glm::rotate(glm::dmat4(1.0), 0.5, glm::normalize(glm::dvec3(0.3, 1.0, 0.6))));
    for (glm::dvec3& p : box.positions)
        p = rotation * p + glm::dvec3(2.0, -1.0, 0.5);
    expectFieldAgrees(testmesh::imported(box, "box"), "box");
}

TEST(MeshMassField, ASphereAgreesWithItsFieldIntegral) {
    expectFieldAgrees(
        testmesh::imported(testmesh::icoSphereSoup({0.1, 0.2, -0.3}, 0.8, 4), "sphere"), "sphere");
}

TEST(MeshMassField, ATorusAgreesWithItsFieldIntegral) {
    expectFieldAgrees(
        testmesh::imported(testmesh::torusSoup({-0.2, 0.4, 0.1}, 1.0, 0.35, 96, 48), "torus"),
        "torus");
}

TEST(MeshMassField, CgalsBunnyAgreesWithItsFieldIntegral) {
    // CGAL's closed, clean bunny (RealMeshTest measures its diagnostics).
    Result<ImportedMesh> mesh = importMesh(SLUICE_CGAL_MESHES "/bunny00.off", {});
    ASSERT_TRUE(mesh.ok()) << mesh.error().message();
    expectFieldAgrees(*mesh, "bunny00.off");
}

TEST(MeshMassField, AssimpsLowPolyBoneAgreesWithItsFieldIntegral) {
    // huesitos.fbx: assimp's closed low-poly bone (120 triangles), the coarsest surface here.
    Result<ImportedMesh> mesh = importMesh(SLUICE_ASSIMP_MODELS "/FBX/huesitos.fbx", {});
    ASSERT_TRUE(mesh.ok()) << mesh.error().message();
    expectFieldAgrees(*mesh, "huesitos.fbx");
}

TEST(MeshMassField, TheStoredMassIsInTheBakeFrameAfterTheImportScale) {
    // An OBJ box imported at scale 0.5: the stored mass is that of the scaled box, where the
    // grid is, and it survives the file.
    const fs::path obj = testmesh::writeTempObj(testmesh::boxSoup({2, 4, 6}, {6, 10, 14}),
                                                "mesh-mass-scale", "box.obj");
    ASSERT_FALSE(obj.empty());
    Result<ImportedMesh> mesh = importMesh(obj, {.scale = 0.5}); // box (1,2,3)-(3,5,7)
    ASSERT_TRUE(mesh.ok()) << mesh.error().message();
    BakeRequest request;
    request.backend = "cgal";
    request.resolution = 8;
    request.scale = 0.5;
    Result<BakeOutcome> outcome = bakeMesh(*mesh, request);
    ASSERT_TRUE(outcome.ok()) << outcome.error().message();
    Result<std::vector<std::byte>> bytes = encodeBaked(outcome->asset);
    ASSERT_TRUE(bytes.ok());
    Result<format::ColliderAsset> read = format::decodeAsset(*bytes, "box.slc");
    ASSERT_TRUE(read.ok()) << read.error().message();
    ASSERT_TRUE(read->meta.meshMass.has_value());
    const format::MassProperties& mass = *read->meta.meshMass;
    // assimp reads OBJ coordinates as floats: these integers come back exactly.
    EXPECT_NEAR(mass.volume, 24.0, 24.0 * 1e-12);
    EXPECT_NEAR(glm::length(mass.centerOfMass - glm::dvec3(2.0, 3.5, 5.0)), 0.0, 1e-12);
    EXPECT_NEAR(mass.inertia[0][0], 50.0, 50.0 * 1e-12);
    EXPECT_NEAR(mass.inertia[1][1], 40.0, 40.0 * 1e-12);
    EXPECT_NEAR(mass.inertia[2][2], 26.0, 26.0 * 1e-12);
    // The centre lies inside the grid, where the field is negative.
    const glm::dvec3 far =
        read->meta.origin + glm::dvec3(read->meta.dims - 1u) * read->meta.voxelSize;
    for (int a = 0; a < 3; ++a) {
        EXPECT_GT(mass.centerOfMass[a], read->meta.origin[a]);
        EXPECT_LT(mass.centerOfMass[a], far[a]);
    }
}

TEST(MeshMassField, AnOpenMeshGetsNoMeshMass) {
    const TriangleSoup open = testmesh::boxSoup({0, 0, 0}, {1, 1, 1}, /*withoutTop=*/true);
    BakeRequest request;
    request.backend = "cgal";
    request.resolution = 8;
    Result<BakeOutcome> outcome = bakeMesh(testmesh::imported(open, "open"), request);
    ASSERT_TRUE(outcome.ok()) << outcome.error().message();
    EXPECT_FALSE(outcome->asset.meta.mesh.closed);
    EXPECT_FALSE(outcome->asset.meta.meshMass.has_value());
}

} // namespace
