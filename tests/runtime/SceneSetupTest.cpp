// Scene setup: derived constants against brute force, block filling, emitters, collider poses.
#include <cmath>
#include <numbers>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "RuntimeTestScenes.h"
#include "VecExpect.h"
#include "sluice/rt/sim/SceneSetup.h"

using namespace sluice;
using sluice::test::expectVecNear;

namespace {

constexpr double kPi = std::numbers::pi;

// The test's own kernels, in double (Müller et al. 2003), independent of SceneSetup.cpp.
double poly6(double q, double h) {
    return q < h ? 315.0 / (64.0 * kPi * std::pow(h, 9)) * std::pow(h * h - q * q, 3) : 0.0;
}
glm::dvec3 spikyGrad(const glm::dvec3& x, double h) {
    const double q = glm::length(x);
    if (q <= 0.0 || q >= h)
        return glm::dvec3(0.0);
    return -45.0 / (kPi * std::pow(h, 6)) * (h - q) * (h - q) * x / q;
}

} // namespace

TEST(DeriveConstants, InteriorLatticeParticleHasRestDensityAndRestStiffness) {
    for (float spacing : {0.02f, 0.013f}) {
        for (float hOverS : {2.0f, 1.7f, 2.5f}) {
            format::Scene scene = testscene::smallScene({7, 7, 7}, spacing);
            scene.simulation.kernelRadius = hOverS * spacing;
            const rt::PbfConstants c = rt::deriveConstants(scene.simulation);
            const std::vector<rt::ParticleState> ps = rt::fillBlocks(scene);
            ASSERT_EQ(ps.size(), 343u);
            const glm::dvec3 xi(ps[3 + 7 * (3 + 7 * 3)].position); // the centre particle
            double rho = 0.0;
            glm::dvec3 gradSum(0.0);
            double gradSq = 0.0;
            for (const rt::ParticleState& p : ps) {
                const glm::dvec3 d = xi - glm::dvec3(p.position);
                rho += c.mass * poly6(glm::length(d), c.h);
                const glm::dvec3 g = double(c.volume) * spikyGrad(d, c.h);
                gradSum += g;
                gradSq += glm::dot(g, g);
            }
            EXPECT_NEAR(rho / 1000.0, 1.0, 1e-5) << "s " << spacing << " h/s " << hOverS;
            const double sBrute = gradSq + glm::dot(gradSum, gradSum);
            EXPECT_NEAR(c.sRest / sBrute, 1.0, 1e-5);
            EXPECT_NEAR(c.volume, c.mass / 1000.0, 1e-6 * c.volume);
        }
    }
}

TEST(DeriveConstants, FollowsTheFormulasOfPbfMd) {
    format::SimulationParams p = testscene::defaultParams(0.02f, 5);
    const rt::PbfConstants c = rt::deriveConstants(p);
    const double h = 0.04;
    EXPECT_FLOAT_EQ(c.h, 0.04f);
    EXPECT_FLOAT_EQ(c.radius, 0.01f);
    EXPECT_FLOAT_EQ(c.dt, float(1.0 / 60.0 / 5.0));
    EXPECT_NEAR(c.poly6 / (315.0 / (64.0 * kPi * std::pow(h, 9))), 1.0, 1e-6);
    EXPECT_NEAR(c.spikyGrad / (-45.0 / (kPi * std::pow(h, 6))), 1.0, 1e-6);
    EXPECT_NEAR(c.epsilon / (0.01 * c.sRest), 1.0, 1e-6);
    EXPECT_NEAR(c.lambdaRef * (c.sRest + c.epsilon), 1.0, 1e-6);
    EXPECT_NEAR(c.wDeltaQ / poly6(0.2 * h, h), 1.0, 1e-6);
    // Mass: rho0 * spacing^3 up to the kernel's discretisation (a few percent at h = 2 s).
    EXPECT_NEAR(c.mass / (1000.0 * 0.02 * 0.02 * 0.02), 1.0, 0.1);
}

TEST(FillBlocks, BoxFillsCellCentresXFastestWithIdsInOrder) {
    format::Scene scene = testscene::emptyScene(0.02f);
    format::FluidBlock box;
    box.min = {1.0f, 0.0f, -0.5f};
    box.max = {1.1f, 0.06f, -0.46f}; // 5 x 3 x 2
    box.velocity = {0.5f, 0.0f, -1.0f};
    scene.blocks.push_back(box);
    format::FluidBlock narrow = box;
    narrow.max.x = 1.099f; // 4.95 spacings: 4 points
    scene.blocks.push_back(narrow);
    const std::vector<rt::ParticleState> ps = rt::fillBlocks(scene);
    ASSERT_EQ(ps.size(), 30u + 24u);
    for (std::uint32_t n = 0; n < ps.size(); ++n)
        EXPECT_EQ(ps[n].id, n);
    expectVecNear(ps[0].position, {1.01f, 0.01f, -0.49f}, 1e-6f);
    expectVecNear(ps[1].position, {1.03f, 0.01f, -0.49f}, 1e-6f);  // x fastest
    expectVecNear(ps[5].position, {1.01f, 0.03f, -0.49f}, 1e-6f);  // then y
    expectVecNear(ps[15].position, {1.01f, 0.01f, -0.47f}, 1e-6f); // then z
    expectVecNear(ps[29].position, {1.09f, 0.05f, -0.47f}, 1e-6f);
    expectVecNear(ps[33].position, {1.07f, 0.01f, -0.49f}, 1e-6f); // second block, 4 per row
    expectVecNear(ps[34].position, {1.01f, 0.03f, -0.49f}, 1e-6f);
    for (const rt::ParticleState& p : ps)
        expectVecNear(p.velocity, box.velocity, 0.0f);
}

TEST(FillBlocks, SphereKeepsLatticePointsWithinRadiusMinusParticleRadius) {
    format::Scene scene = testscene::emptyScene(0.02f);
    format::FluidBlock sphere;
    sphere.shape = format::FluidBlock::Shape::Sphere;
    sphere.center = {0.3f, 0.2f, 0.1f};
    sphere.radius = 0.05f; // reach 0.04 = 2 spacings: i^2 + j^2 + k^2 <= 4
    scene.blocks.push_back(sphere);
    sphere.radius = 0.07f; // reach exactly 3 spacings: i^2 + j^2 + k^2 <= 9
    scene.blocks.push_back(sphere);
    const std::vector<rt::ParticleState> ps = rt::fillBlocks(scene);
    int expected4 = 0, expected9 = 0;
    for (int k = -3; k <= 3; ++k)
        for (int j = -3; j <= 3; ++j)
            for (int i = -3; i <= 3; ++i) {
                expected4 += i * i + j * j + k * k <= 4;
                expected9 += i * i + j * j + k * k <= 9;
            }
    ASSERT_EQ(expected4, 33);
    ASSERT_EQ(ps.size(), std::size_t(expected4 + expected9));
    expectVecNear(ps[0].position, {0.3f, 0.2f, 0.06f}, 1e-6f); // (0, 0, -2): z outermost
    expectVecNear(ps[16].position, {0.3f, 0.2f, 0.1f}, 1e-6f); // the centre is the middle one
    EXPECT_EQ(ps.back().id, std::uint32_t(ps.size() - 1));
    std::set<std::tuple<int, int, int>> unique;
    for (const rt::ParticleState& p : ps) {
        EXPECT_LE(glm::length(p.position - sphere.center), 0.06f + 1e-6f);
        unique.insert({int(std::lround(p.position.x / 0.02f)),
                       int(std::lround(p.position.y / 0.02f)),
                       int(std::lround(p.position.z / 0.02f))});
    }
    EXPECT_EQ(unique.size(), std::size_t(expected9)); // the second sphere covers the first
}

TEST(EmitterDisc, HoldsTheLatticePointsOfTheDiscPerpendicularToTheDirection) {
    format::Emitter e;
    e.direction = glm::normalize(glm::vec3(1.0f, -2.0f, 0.5f));
    e.radius = 0.04f; // a^2 + b^2 <= 4
    EXPECT_EQ(rt::emitterDisc(e, 0.02f).size(), 13u);
    e.radius = 0.06f; // a^2 + b^2 <= 9; 3 * 0.02f > 0.06f in float, kept by the slack
    const std::vector<glm::vec3> disc = rt::emitterDisc(e, 0.02f);
    ASSERT_EQ(disc.size(), 29u);
    for (const glm::vec3& p : disc) {
        EXPECT_NEAR(glm::dot(p, e.direction), 0.0f, 1e-6f);
        EXPECT_LE(glm::length(p), 0.06f + 1e-6f);
    }
    for (std::size_t a = 0; a < disc.size(); ++a)
        for (std::size_t b = a + 1; b < disc.size(); ++b)
            EXPECT_GT(glm::length(disc[a] - disc[b]), 0.02f - 1e-5f);
    e.direction = {0.0f, -1.0f, 0.0f}; // |d.y| >= 0.9
    const std::vector<glm::vec3> down = rt::emitterDisc(e, 0.02f);
    // u = normalize(d x (1,0,0)) = (0,0,1), w = d x u = (-1,0,0); b outer, a inner: the first
    // point is (a, b) = (0, -3), the second (-2, -2).
    ASSERT_EQ(down.size(), 29u);
    expectVecNear(down[0], {0.06f, 0.0f, 0.0f}, 1e-6f);
    expectVecNear(down[1], {0.04f, 0.0f, -0.04f}, 1e-6f);
}

TEST(EmitterSchedule, EmitsSpeedOverSpacingLayersPerSecondWithTheirAges) {
    format::Scene scene = testscene::emptyScene(0.02f, 4, 100000);
    format::Emitter e;
    e.position = {0.0f, 1.0f, 0.0f};
    e.direction = {0.0f, -1.0f, 0.0f};
    e.radius = 0.04f;
    e.speed = 1.0f; // interval 0.02 s: 50 layers per second
    e.start = 0.0f;
    e.stop = 1.0f;
    scene.emitters.push_back(e);
    rt::EmitterSchedule schedule(scene);
    const double dt = 1.0 / 240.0;
    std::vector<rt::ParticleState> all;
    std::uint32_t nextId = 7;
    for (int n = 0; n < 300; ++n) {
        const float t = float(n * dt);
        std::vector<rt::ParticleState> fresh;
        ASSERT_TRUE(schedule.emit(t, std::uint32_t(all.size()), 100000, nextId, fresh));
        for (const rt::ParticleState& p : fresh) {
            // Moved along the direction by speed * age, age in [0, dt).
            const float travelled = 1.0f - p.position.y;
            EXPECT_GE(travelled, -1e-6f);
            EXPECT_LT(travelled, float(dt) + 1e-6f);
            expectVecNear(p.velocity, {0.0f, -1.0f, 0.0f}, 0.0f);
        }
        all.insert(all.end(), fresh.begin(), fresh.end());
        EXPECT_EQ(schedule.finished(t), t >= 1.0f);
    }
    // Last substep before stop at t = 239/240: floor(0.99583 / 0.02) + 1 = 50 layers.
    ASSERT_EQ(all.size(), 50u * 13u);
    for (std::size_t n = 0; n < all.size(); ++n)
        EXPECT_EQ(all[n].id, 7u + n);
    EXPECT_EQ(nextId, 7u + 650u);
}

TEST(EmitterSchedule, RateCapsTheLayerIntervalAndCapacityIsReported) {
    format::Scene scene = testscene::emptyScene(0.02f);
    format::Emitter e;
    e.radius = 0.04f;
    e.speed = 1.0f;
    e.rate = 130.0f; // 13 particles per layer: 10 layers per second
    e.stop = 1.0f;
    scene.emitters.push_back(e);
    rt::EmitterSchedule schedule(scene);
    std::uint32_t nextId = 0;
    std::vector<rt::ParticleState> out;
    for (int n = 0; n < 240; ++n)
        ASSERT_TRUE(schedule.emit(float(n / 240.0), std::uint32_t(out.size()), 1000, nextId, out));
    EXPECT_EQ(out.size(), 10u * 13u);

    rt::EmitterSchedule capped(scene);
    std::vector<rt::ParticleState> few;
    nextId = 0;
    EXPECT_TRUE(capped.emit(0.0f, 5, 25, nextId, few)); // 5 + 13 = 18 fit
    EXPECT_EQ(few.size(), 13u);
    EXPECT_FALSE(capped.emit(0.1f, 5, 25, nextId, few)); // only 7 of the next 13 fit
    EXPECT_EQ(few.size(), 20u);
    EXPECT_EQ(nextId, 20u);
}

TEST(ColliderPose, ToLocalInvertsToWorld) {
    format::SceneCollider c;
    c.translation = {0.3f, -1.0f, 2.0f};
    c.rotationDegrees = {30.0f, -45.0f, 110.0f};
    c.scale = 2.5f;
    const rt::ColliderPose pose = rt::colliderPose(c, 0.0f);
    for (glm::vec3 p :
         {glm::vec3(0.0f), glm::vec3(1.0f, 2.0f, 3.0f), glm::vec3(-0.2f, 0.7f, 0.1f)}) {
        expectVecNear(pose.toLocal(pose.toWorld(p)), p, 1e-5f);
        EXPECT_NEAR(glm::length(pose.toWorld(p) - c.translation), 2.5f * glm::length(p), 1e-5f);
    }
}

TEST(ColliderPose, EulerDegreesApplyXThenYThenZ) {
    const glm::quat q = rt::eulerDegrees({90.0f, 0.0f, 90.0f}); // Rz * Rx
    expectVecNear(q * glm::vec3(1, 0, 0), {0, 1, 0}, 1e-6f);    // Rx keeps x, Rz: x -> y
    expectVecNear(q * glm::vec3(0, 1, 0), {0, 0, 1}, 1e-6f);    // Rx: y -> z, Rz keeps z
    const glm::quat y = rt::eulerDegrees({0.0f, 90.0f, 0.0f});
    expectVecNear(y * glm::vec3(0, 0, 1), {1, 0, 0}, 1e-6f);
}

TEST(ColliderPose, KeyframesInterpolateLinearlyAndSlerpAndClamp) {
    format::SceneCollider c;
    c.translation = {9.0f, 9.0f, 9.0f};    // replaced by the keys
    c.linearVelocity = {5.0f, 0.0f, 0.0f}; // ignored with keys
    c.scale = 0.5f;
    c.keys = {{1.0f, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}},
              {3.0f, {2.0f, 4.0f, 0.0f}, {0.0f, 0.0f, 90.0f}},
              {4.0f, {2.0f, 4.0f, 1.0f}, {0.0f, 0.0f, 90.0f}}};
    const rt::ColliderPose mid = rt::colliderPose(c, 2.0f);
    expectVecNear(mid.translation, {1.0f, 2.0f, 0.0f}, 1e-6f);
    const float h = std::sqrt(0.5f);
    expectVecNear(mid.rotation * glm::vec3(1, 0, 0), {h, h, 0.0f}, 1e-6f); // 45 degrees about z
    EXPECT_FLOAT_EQ(mid.scale, 0.5f);
    expectVecNear(rt::colliderPose(c, 3.5f).translation, {2.0f, 4.0f, 0.5f}, 1e-6f);
    const rt::ColliderPose before = rt::colliderPose(c, -2.0f);
    expectVecNear(before.translation, glm::vec3(0.0f), 0.0f);
    expectVecNear(before.rotation * glm::vec3(1, 0, 0), {1, 0, 0}, 1e-6f);
    const rt::ColliderPose after = rt::colliderPose(c, 10.0f);
    expectVecNear(after.translation, {2.0f, 4.0f, 1.0f}, 0.0f);
    expectVecNear(after.rotation * glm::vec3(1, 0, 0), {0, 1, 0}, 1e-6f);
}

TEST(ColliderPose, VelocitiesMoveAndTurnAfterTheRestRotation) {
    format::SceneCollider c;
    c.translation = {1.0f, 0.0f, 0.0f};
    c.rotationDegrees = {90.0f, 0.0f, 0.0f};
    c.linearVelocity = {0.0f, 0.5f, 0.0f};
    c.angularVelocityDegrees = {0.0f, 0.0f, 45.0f};
    const rt::ColliderPose p0 = rt::colliderPose(c, 0.0f);
    expectVecNear(p0.toWorld({0, 1, 0}), {1.0f, 0.0f, 1.0f}, 1e-6f); // R0: y -> z
    const rt::ColliderPose p2 = rt::colliderPose(c, 2.0f);           // 90 degrees about z
    expectVecNear(p2.translation, {1.0f, 1.0f, 0.0f}, 1e-6f);
    // R(t) = AxisAngle(w t) * R0: x stays x under R0, then turns to y. (R0 * AxisAngle would
    // give z.)
    expectVecNear(p2.toWorld({1, 0, 0}) - p2.translation, {0, 1, 0}, 1e-6f);
    expectVecNear(p2.toWorld({0, 1, 0}) - p2.translation, {0, 0, 1}, 1e-6f);
}
