// A capsule collider from its shape (format::shapeCollider) against the same capsule's mesh baked
// on the GPU: the two fields agree within a voxel, and so do their volumes and inertia.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "../gpu/GpuTest.h"
#include "TestMeshes.h"
#include "sluice/bake/gpu/GpuBaker.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/format/asset/ShapeCollider.h"

namespace sluice::test {
namespace {

using namespace sluice::bake;

class ShapeBakeTest : public gpu::test::GpuTest {};

TEST_F(ShapeBakeTest, CapsuleAgreesWithTheBakedCapsuleWithinAVoxel) {
    format::ColliderShape shape;
    shape.kind = format::ColliderShape::Kind::Capsule;
    shape.radius = 0.08f;
    shape.height = 0.36f; // caps' centres at y = +-0.1
    shape.voxelSize = 0.01f;
    auto fromShape = format::shapeCollider(shape);
    ASSERT_TRUE(fromShape) << fromShape.error().message();
    // 96 meridians and 48 bands: the mesh lies within 0.2 mm of the capsule, 1/50 of a voxel.
    const ImportedMesh mesh =
        testmesh::imported(testmesh::capsuleSoup(0.08, 0.1, 96, 48), "capsule");
    ASSERT_TRUE(mesh.diagnostics.closed);
    const BakeSettings settings{.grid = {.voxelSize = 0.01}};
    auto baked = bakeGpu(mesh, settings, context());
    ASSERT_TRUE(baked) << baked.error().message();

    // Both read as the solver reads them, at points within the band the solver samples (the
    // kernel radius of 2 cm particles, 4 cm, each side of the surface).
    const format::SdfSampler a(*fromShape), b(*baked);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worst = 0.0, sum = 0.0;
    int n = 0;
    while (n < 4000) {
        const glm::dvec3 p(0.13 * u(rng), 0.31 * u(rng), 0.13 * u(rng));
        if (std::abs(format::shapeDistance(shape, p)) > 0.04)
            continue;
        const double d = std::abs(a.value(p) - b.value(p));
        worst = std::max(worst, d);
        sum += d;
        ++n;
    }
    EXPECT_LT(worst, shape.voxelSize) << "mean " << sum / n;
    EXPECT_LT(sum / n, 0.1 * shape.voxelSize);

    // The mesh's exact mass properties (polyhedral integrals) against the closed form: the
    // mesh is inscribed, so a little smaller, by its tessellation's share.
    ASSERT_TRUE(baked->meta.meshMass);
    const format::MassProperties& exact = *fromShape->meta.meshMass;
    const format::MassProperties& polyhedral = *baked->meta.meshMass;
    EXPECT_NEAR(polyhedral.volume, exact.volume, 0.005 * exact.volume);
    EXPECT_LE(polyhedral.volume, exact.volume);
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(polyhedral.inertia[i][i], exact.inertia[i][i], 0.01 * exact.inertia[i][i]);
}

} // namespace
} // namespace sluice::test
