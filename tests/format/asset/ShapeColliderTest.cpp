// Shape colliders (ShapeCollider.h): the closed-form distances, the sampled grid and its exact
// mass properties, the scene keys that ask for them, and the bad sizes each refused by name.
#include <cmath>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "asset/AssetTestUtil.h"
#include "sluice/format/asset/MassProperties.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/format/asset/ShapeCollider.h"
#include "sluice/format/scene/SceneDefaults.h"
#include "sluice/format/scene/SceneIO.h"

namespace sluice::test {
namespace {

using namespace sluice::format;
constexpr double kPi = std::numbers::pi;

ColliderShape capsule(float radius, float height, float voxel) {
    ColliderShape s;
    s.kind = ColliderShape::Kind::Capsule;
    s.radius = radius;
    s.height = height;
    s.voxelSize = voxel;
    return s;
}

ColliderShape box(glm::vec3 size, float voxel) {
    ColliderShape s;
    s.kind = ColliderShape::Kind::Box;
    s.size = size;
    s.voxelSize = voxel;
    return s;
}

ColliderShape sphere(float radius, float voxel) {
    ColliderShape s;
    s.radius = radius;
    s.voxelSize = voxel;
    return s;
}

TEST(ShapeCollider, DistancesAreTheShapesOwn) {
    // Points whose distance follows from the geometry by hand.
    const ColliderShape c = capsule(0.1f, 0.5f, 0.01f);         // caps' centres at y = +-0.15
    EXPECT_NEAR(shapeDistance(c, {0.3, 0.0, 0.0}), 0.2, 1e-7);  // beside the cylinder
    EXPECT_NEAR(shapeDistance(c, {0.0, 0.45, 0.0}), 0.2, 1e-7); // over the top tip
    EXPECT_NEAR(shapeDistance(c, {0.0, 0.0, 0.0}), -0.1, 1e-7); // on the axis
    EXPECT_NEAR(shapeDistance(c, {0.3, 0.45, 0.0}), std::sqrt(0.09 + 0.09) - 0.1, 1e-7);
    const ColliderShape b = box({0.2f, 0.4f, 0.6f}, 0.01f);
    EXPECT_NEAR(shapeDistance(b, {0.0, 0.0, 0.0}), -0.1, 1e-7); // nearest face: x
    EXPECT_NEAR(shapeDistance(b, {0.2, 0.0, 0.0}), 0.1, 1e-7);
    EXPECT_NEAR(shapeDistance(b, {0.4, 0.5, 0.3}), std::sqrt(0.09 + 0.09), 1e-6); // an edge
    EXPECT_NEAR(shapeDistance(sphere(0.25f, 0.01f), {0.0, 0.0, -1.0}), 0.75, 1e-7);
}

TEST(ShapeCollider, GridIsCentredPaddedAndHoldsTheExactDistances) {
    const ColliderShape c = capsule(0.1f, 0.5f, 0.01f);
    auto asset = shapeCollider(c);
    ASSERT_TRUE(asset) << asset.error().message();
    const ColliderMeta& m = asset->meta;
    EXPECT_EQ(m.layout, Layout::Dense);
    EXPECT_DOUBLE_EQ(m.voxelSize, double(c.voxelSize));
    // Reaches the padding beyond the shape on every side, centred on the origin.
    const glm::dvec3 far = m.origin + glm::dvec3(m.dims - 1u) * m.voxelSize;
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(far[a], -m.origin[a], 1e-12);
    EXPECT_GE(far.y, 0.25 + kShapePaddingVoxels * 0.01 - 1e-9);
    EXPECT_GE(far.x, 0.10 + kShapePaddingVoxels * 0.01 - 1e-9);
    EXPECT_EQ(asset->distances.size(), std::size_t(m.dims.x) * m.dims.y * m.dims.z);
    // Each sample is the distance at its grid point, to float rounding.
    std::mt19937 rng(7);
    for (int n = 0; n < 200; ++n) {
        const glm::uvec3 g(rng() % m.dims.x, rng() % m.dims.y, rng() % m.dims.z);
        const double exact = shapeDistance(c, m.origin + glm::dvec3(g) * m.voxelSize);
        const float stored = asset->distances[g.x + m.dims.x * (g.y + m.dims.y * g.z)];
        EXPECT_NEAR(stored, exact, 1e-6) << g.x << " " << g.y << " " << g.z;
    }
    // Read between the samples as the solver reads, the field stays within a tenth of a voxel of
    // the capsule's distance near its surface.
    const SdfSampler sampler(*asset);
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    double worst = 0.0;
    for (int n = 0; n < 2000; ++n) {
        const glm::dvec3 p(u(rng), 1.5 * u(rng), u(rng));
        const double exact = shapeDistance(c, p);
        if (std::abs(exact) < 0.03)
            worst = std::max(worst, std::abs(sampler.value(p) - exact));
    }
    EXPECT_LT(worst, 0.1 * c.voxelSize);
}

TEST(ShapeCollider, MassPropertiesAreExactAndMatchTheFieldsIntegral) {
    const double r = 0.1, h = 0.5, a = 0.15;
    const MassProperties cap = shapeMass(capsule(float(r), float(h), 0.005f));
    const double cylinder = kPi * r * r * 2.0 * a, ball = 4.0 / 3.0 * kPi * r * r * r;
    EXPECT_NEAR(cap.volume, cylinder + ball, 1e-6 * cap.volume); // r and h held in float
    const MassProperties b = shapeMass(box({0.2f, 0.4f, 0.6f}, 0.01f));
    EXPECT_NEAR(b.volume, 0.2 * 0.4 * 0.6, 1e-6 * b.volume);
    EXPECT_NEAR(b.inertia[0][0], b.volume / 12.0 * (0.16 + 0.36), 1e-6 * b.inertia[0][0]);
    const MassProperties s = shapeMass(sphere(0.25f, 0.01f));
    EXPECT_NEAR(s.inertia[1][1], 0.4 * s.volume * 0.0625, 1e-6 * s.inertia[1][1]);
    // The closed forms against the integral of each sampled field (MassProperties.h), which
    // knows nothing of the shape: within the integral's own error, a few tenths of a percent of
    // the volume and 2 % of the inertia (its smoothed edges weigh the box's corners, far from
    // the centre, 1.3 % heavier at 5 mm voxels on a 10 cm box).
    for (const ColliderShape& shape : {capsule(float(r), float(h), 0.005f),
                                       box({0.2f, 0.1f, 0.15f}, 0.005f), sphere(0.1f, 0.005f)}) {
        auto asset = shapeCollider(shape);
        ASSERT_TRUE(asset);
        auto integrated = massPropertiesFromField(*asset);
        ASSERT_TRUE(integrated) << integrated.error().message();
        const MassProperties exact = *asset->meta.meshMass;
        EXPECT_NEAR(integrated->volume, exact.volume, 0.005 * exact.volume)
            << shapeName(shape.kind);
        for (int i = 0; i < 3; ++i)
            EXPECT_NEAR(integrated->inertia[i][i], exact.inertia[i][i], 0.02 * exact.inertia[i][i])
                << shapeName(shape.kind) << " axis " << i;
        EXPECT_LT(glm::length(integrated->centerOfMass), 1e-3 * shape.voxelSize);
    }
}

TEST(ShapeCollider, RefusesBadSizesByName) {
    auto negative = shapeCollider(sphere(-1.0f, 0.01f));
    ASSERT_FALSE(negative);
    EXPECT_EQ(negative.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(negative.error().detail.find("sphere.radius"), std::string::npos);
    auto shortCapsule = shapeCollider(capsule(0.2f, 0.3f, 0.01f));
    ASSERT_FALSE(shortCapsule);
    EXPECT_NE(shortCapsule.error().detail.find("capsule.height"), std::string::npos);
    auto flat = shapeCollider(box({1.0f, 0.0f, 1.0f}, 0.01f));
    ASSERT_FALSE(flat);
    EXPECT_NE(flat.error().detail.find("box.size"), std::string::npos);
    auto nan = shapeCollider(box({1.0f, NAN, 1.0f}, 0.01f));
    ASSERT_FALSE(nan);
    // A 10 m box at 1 cm voxels is a billion samples: refused before any is allocated.
    auto huge = shapeCollider(box({10.0f, 10.0f, 10.0f}, 0.01f));
    ASSERT_FALSE(huge);
    EXPECT_EQ(huge.error().code, ErrorCode::SizeOverflow);
    EXPECT_NE(huge.error().detail.find("box.voxel"), std::string::npos) << huge.error().detail;
}

const char* kFluid = R"("fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}])";

Result<Scene> sceneWith(const std::string& collider) {
    return parseScene(std::string("{") + kFluid + R"(, "colliders": [)" + collider + "]}", "s.json",
                      {.checkAssets = false});
}

TEST(ShapeCollider, SceneKeysReadEachShapeWithTheDerivedVoxel) {
    auto read = sceneWith(R"({"shape": {"capsule": {"radius": 0.2, "height": 1.0}},
                              "translation": [1, 0, 0]},
                             {"shape": {"box": {"size": [1, 2, 3], "voxel": 0.05}}},
                             {"shape": {"sphere": {"radius": 0.5}}})");
    ASSERT_TRUE(read) << read.error().message();
    ASSERT_EQ(read->colliders.size(), 3u);
    const ColliderShape& c = *read->colliders[0].shape;
    EXPECT_EQ(c.kind, ColliderShape::Kind::Capsule);
    EXPECT_FLOAT_EQ(c.radius, 0.2f);
    EXPECT_FLOAT_EQ(c.height, 1.0f);
    EXPECT_FLOAT_EQ(c.voxelSize, defaultShapeVoxel(0.02f)); // the default spacing's half
    EXPECT_TRUE(read->colliders[0].asset.empty());
    EXPECT_EQ(read->colliders[1].shape->size, glm::vec3(1.0f, 2.0f, 3.0f));
    EXPECT_FLOAT_EQ(read->colliders[1].shape->voxelSize, 0.05f);
    EXPECT_EQ(colliderName(read->colliders[2]), "sphere");
    // completeScene derives the voxel of a shape built in code the same way.
    Scene scene;
    scene.simulation.capacity = 10;
    scene.colliders.emplace_back();
    scene.colliders[0].shape = sphere(0.1f, 0.0f);
    ASSERT_TRUE(completeScene(scene));
    EXPECT_FLOAT_EQ(scene.colliders[0].shape->voxelSize, 0.01f);
}

TEST(ShapeCollider, SceneRefusesBadShapesNamingTheKey) {
    const std::pair<const char*, const char*> cases[] = {
        {R"({"asset": "a.slc", "shape": {"sphere": {"radius": 1}}})", "has both"},
        {R"({"translation": [0, 0, 0]})", "\"asset\""},
        {R"({"shape": {"cone": {"radius": 1}}})", "cone"},
        {R"({"shape": {"sphere": {"radius": 1}, "box": {"size": [1, 1, 1]}}})", "exactly one"},
        {R"({"shape": {"sphere": {"radius": -1}}})", "colliders[0].shape.sphere.radius"},
        {R"({"shape": {"sphere": {"size": [1, 1, 1]}}})", "colliders[0].shape.sphere.size"},
        {R"({"shape": {"capsule": {"radius": 0.5, "height": 0.5}}})",
         "colliders[0].shape.capsule.height"},
        {R"({"shape": {"box": {"size": [1, 0, 1]}}})", "colliders[0].shape.box.size"},
        {R"({"shape": {"box": {"size": [1, 1, 1], "voxel": 0}}})", "colliders[0].shape.box.voxel"},
    };
    for (const auto& [collider, expected] : cases) {
        auto read = sceneWith(collider);
        ASSERT_FALSE(read) << collider;
        EXPECT_NE(read.error().message().find(expected), std::string::npos)
            << collider << " -> " << read.error().message();
    }
    // A shape built in code with a bad size: completeScene names it and changes nothing.
    Scene scene;
    scene.simulation.capacity = 10;
    scene.colliders.emplace_back();
    scene.colliders[0].shape = capsule(0.5f, 0.2f, 0.0f);
    auto bad = completeScene(scene);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().detail.find("colliders[0].shape.capsule.height"), std::string::npos)
        << bad.error().detail;
    EXPECT_EQ(scene.colliders[0].shape->voxelSize, 0.0f);
}

} // namespace
} // namespace sluice::test
