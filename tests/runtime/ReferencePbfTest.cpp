// The CPU reference PBF (tests/reference) against closed-form motion and physical invariants.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "ReferencePbf.h"
#include "RuntimeTestScenes.h"
#include "VecExpect.h"

using namespace sluice;
using sluice::test::expectVecNear;

namespace {

constexpr float kSpacing = 0.02f;
constexpr float kRadius = 0.5f * kSpacing;

/// A scene with every parameter set and one particle; the test places it.
format::Scene oneParticleScene() {
    format::Scene scene = testscene::emptyScene(kSpacing, 4, 16);
    format::FluidBlock block;
    block.min = glm::vec3(0.0f);
    block.max = glm::vec3(kSpacing);
    scene.blocks.push_back(block);
    return scene;
}

/// The solid box [-0.5, 0.5] x [-0.2, 0] x [-0.5, 0.5]: a floor whose top face is y = 0.
const format::ColliderAsset& floorAsset() {
    static const format::ColliderAsset asset =
        testscene::boxColliderAsset({-0.5, -0.2, -0.5}, {0.5, 0.0, 0.5}, 0.02);
    return asset;
}

ref::ReferenceCollider floorCollider(float friction = 0.0f) {
    ref::ReferenceCollider c;
    c.asset = &floorAsset();
    c.placement.asset = "floor.sdf";
    c.placement.friction = friction;
    return c;
}

void place(ref::ReferencePbf& sim, std::size_t i, glm::vec3 x, glm::vec3 v) {
    sim.mutableParticles()[i].position = x;
    sim.mutableParticles()[i].velocity = v;
}

} // namespace

TEST(ReferencePbf, FreeParticleFollowsSymplecticEuler) {
    format::Scene scene = oneParticleScene();
    ref::ReferencePbf sim(scene, {});
    const glm::vec3 x0(0.1f, 1.0f, 0.2f), v0(0.5f, 2.0f, -0.3f);
    place(sim, 0, x0, v0);
    const float dt = sim.constants().dt;
    const glm::vec3 g = scene.simulation.gravity;
    glm::vec3 x = x0, v = v0; // the same float operations, by hand
    for (int n = 1; n <= 40; ++n) {
        sim.substep();
        v += dt * g;
        const glm::vec3 xs = x + dt * v;
        v = (xs - x) / dt;
        x = xs;
        const rt::ParticleState& p = sim.particles()[0];
        expectVecNear(p.position, x, 1e-6f);
        expectVecNear(p.velocity, v, 1e-5f);
        // Closed form of symplectic Euler: x0 + n dt v0 + g dt^2 n (n + 1) / 2 (explicit Euler
        // would give n (n - 1) / 2, 7e-3 m away after 40 substeps). The float velocity
        // (x* - x) / dt loses about ulp(x) / dt per substep, hence 1e-4.
        const glm::dvec3 exact =
            glm::dvec3(x0) + double(n) * double(dt) * glm::dvec3(v0) +
            glm::dvec3(g) * double(dt) * double(dt) * double(n * (n + 1)) / 2.0;
        expectVecNear(p.position, glm::vec3(exact), 1e-4f);
    }
    EXPECT_NEAR(sim.time(), 40.0 * dt, 1e-6);
}

TEST(ReferencePbf, ParticleRestsOnABoxFloorWithoutSinking) {
    ref::ReferencePbf sim(oneParticleScene(), {floorCollider()});
    const glm::vec3 x0(0.05f, kRadius, -0.03f);
    place(sim, 0, x0, glm::vec3(0.0f));
    for (int s = 0; s < 60; ++s) {
        sim.step();
        const rt::ParticleState& p = sim.particles()[0];
        EXPECT_GE(sim.colliderDistance(p.position, sim.time()), kRadius - 1e-6f);
        expectVecNear(p.position, x0, 1e-6f);
        EXPECT_LT(glm::length(p.velocity), 1e-3f);
        EXPECT_EQ(sim.stats().insideColliders, 0u);
    }
}

TEST(ReferencePbf, RestLatticeWithoutGravityHasNoDensityErrorAndStaysPut) {
    format::Scene scene = testscene::smallScene({6, 6, 6}, kSpacing);
    scene.domainMin.reset();
    scene.domainMax.reset();
    scene.simulation.gravity = glm::vec3(0.0f);
    scene.simulation.scorrK = 0.0f;
    ref::ReferencePbf sim(scene, {});
    const std::vector<rt::ParticleState> start = sim.particles();
    for (int s = 0; s < 10; ++s) {
        sim.step();
        EXPECT_LT(sim.stats().avgDensityError, 1e-6);
        EXPECT_LT(sim.stats().maxDensityError, 1e-5);
    }
    for (std::size_t i = 0; i < start.size(); ++i)
        expectVecNear(sim.particles()[i].position, start[i].position, 1e-6f);

    // With s_corr on, one iteration leaves the interior (full, symmetric neighbourhoods) in
    // place and pushes the surface layer outward: s_corr is a repulsion. (Later iterations
    // carry the surface's motion inward, one layer each.)
    scene.simulation.scorrK = 0.1f;
    scene.simulation.minIterations = 1;
    scene.simulation.maxIterations = 1;
    ref::ReferencePbf repulsive(scene, {});
    repulsive.substep();
    const glm::vec3 centre(3.0f * kSpacing);
    for (std::size_t i = 0; i < start.size(); ++i) {
        const glm::uvec3 ijk(i % 6, (i / 6) % 6, i / 36);
        const bool surface =
            glm::any(glm::equal(ijk, glm::uvec3(0))) || glm::any(glm::equal(ijk, glm::uvec3(5)));
        const glm::vec3 moved = repulsive.particles()[i].position - start[i].position;
        if (surface)
            EXPECT_GT(glm::dot(moved, start[i].position - centre), 1e-7f) << "particle " << i;
        else
            EXPECT_LT(glm::length(moved), 1e-7f) << "particle " << i;
    }
}

TEST(ReferencePbf, SolveAndXsphConserveMomentum) {
    format::Scene scene = testscene::emptyScene(kSpacing, 4, 216);
    scene.simulation.gravity = glm::vec3(0.0f);
    scene.simulation.vorticity = 0.0f; // confinement adds momentum by design
    scene.simulation.xsph = 0.1f;
    format::FluidBlock block;
    block.max = glm::vec3(6.0f * kSpacing);
    scene.blocks.push_back(block);
    ref::ReferencePbf sim(scene, {});
    ASSERT_EQ(sim.particles().size(), 216u);
    // Squeeze into 60 % of the volume with jitter and random velocities: strongly compressed.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> jitter(-0.2f * kSpacing, 0.2f * kSpacing), vel(-1, 1);
    glm::dvec3 before(0.0);
    for (rt::ParticleState& p : sim.mutableParticles()) {
        p.position = 0.85f * p.position + glm::vec3(jitter(rng), jitter(rng), jitter(rng));
        p.velocity = glm::vec3(vel(rng), vel(rng), vel(rng));
        before += glm::dvec3(p.velocity);
    }
    const std::vector<rt::ParticleState> start = sim.particles();
    sim.substep();
    glm::dvec3 after(0.0);
    double changed = 0.0;
    for (std::size_t i = 0; i < start.size(); ++i) {
        after += glm::dvec3(sim.particles()[i].velocity);
        changed += glm::length(sim.particles()[i].velocity - start[i].velocity);
    }
    EXPECT_GT(changed / double(start.size()), 0.5); // mean |dv| [m/s]: the solve had work to do
    EXPECT_LT(glm::length(after - before), 1e-5 * changed);
}

TEST(ReferencePbf, HydrostaticColumnSettlesBelowOnePercentDensityError) {
    // 6 x 12 x 6 particles standing in a tank that fits them exactly; defaults otherwise
    // (4 substeps of 1/60 s, 8 iterations).
    const format::Scene scene = testscene::smallScene({6, 12, 6}, kSpacing);
    ref::ReferencePbf sim(scene, {});
    for (int s = 0; s < 120; ++s) {
        sim.step();
        ASSERT_EQ(sim.stats().nonFinite, 0u);
    }
    EXPECT_LT(sim.stats().avgDensityError, 0.01);
    EXPECT_LT(sim.stats().maxDensityError, 0.05);
    EXPECT_LT(sim.stats().maxSpeed, 0.05); // settled after 2 s
    double meanY = 0.0;
    for (const rt::ParticleState& p : sim.particles()) {
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(p.position[a], (*scene.domainMin)[a] + kRadius - 1e-6f);
            EXPECT_LE(p.position[a], (*scene.domainMax)[a] - kRadius + 1e-6f);
        }
        meanY += p.position.y / double(sim.particles().size());
    }
    // Neither collapsed nor blown up: the start had mean height 0.12 m. (Walls without boundary
    // particles let the column sink by about a particle radius.)
    EXPECT_GT(meanY, 0.10);
    EXPECT_LT(meanY, 0.13);
}

TEST(ReferencePbf, NonFiniteParticleIsResetAndCounted) {
    format::Scene scene = testscene::smallScene({4, 4, 4}, kSpacing);
    ref::ReferencePbf sim(scene, {});
    const std::vector<rt::ParticleState> start = sim.particles();
    sim.mutableParticles()[5].velocity.y = std::numeric_limits<float>::quiet_NaN();
    sim.substep();
    EXPECT_EQ(sim.stats().nonFinite, 1u);
    // Reset at the prediction (docs/pbf.md step 2): back at x, at rest, then solved with the
    // rest, so it moves no more than the settling column moves the others (gravity's g dt^2 =
    // 0.17 mm, and the solve's corrections).
    float othersMoved = 0.0f;
    for (std::size_t i = 0; i < start.size(); ++i)
        if (i != 5)
            othersMoved =
                std::max(othersMoved, glm::length(sim.particles()[i].position - start[i].position));
    EXPECT_GT(othersMoved, 1e-4f);
    EXPECT_LE(glm::length(sim.particles()[5].position - start[5].position), othersMoved);
    EXPECT_LT(glm::length(sim.particles()[5].velocity), 0.05f);
    for (const rt::ParticleState& p : sim.particles())
        EXPECT_TRUE(std::isfinite(glm::dot(p.position, p.velocity)));
    sim.step();
    EXPECT_EQ(sim.stats().nonFinite, 0u);

    // A position that is not finite stays so: reset to itself at the prediction and after the
    // solve in each of the 4 substeps, and it never becomes anybody's neighbour.
    sim.mutableParticles()[7].position.x = std::numeric_limits<float>::infinity();
    sim.step();
    EXPECT_EQ(sim.stats().nonFinite, 8u);
    for (const rt::ParticleState& p : sim.particles()) {
        if (p.id == 7)
            continue;
        EXPECT_TRUE(std::isfinite(glm::dot(p.position, p.velocity)));
    }
}

TEST(ReferencePbf, FrictionRemovesThatShareOfTangentialSlipOnAStaticFloor) {
    for (float friction : {0.0f, 0.5f, 1.0f}) {
        ref::ReferencePbf sim(oneParticleScene(), {floorCollider(friction)});
        place(sim, 0, {0.0f, kRadius, 0.0f}, {1.0f, 0.0f, 0.0f});
        const float dt = sim.constants().dt;
        sim.substep();
        const rt::ParticleState& p = sim.particles()[0];
        EXPECT_NEAR(p.position.x, (1.0f - friction) * dt, 1e-7f) << "friction " << friction;
        EXPECT_NEAR(p.position.y, kRadius, 1e-7f);
        EXPECT_NEAR(p.velocity.x, 1.0f - friction, 1e-4f);
        EXPECT_NEAR(p.velocity.y, 0.0f, 1e-4f);
    }
}

TEST(ReferencePbf, TiltedScaledColliderPushesAlongItsWorldNormal) {
    ref::ReferenceCollider tilted = floorCollider();
    tilted.placement.rotationDegrees = {0.0f, 0.0f, 30.0f};
    tilted.placement.translation = {1.0f, 2.0f, 3.0f};
    tilted.placement.scale = 1.5f;
    format::Scene scene = oneParticleScene();
    scene.simulation.gravity = glm::vec3(0.0f);
    ref::ReferencePbf sim(scene, {tilted});
    place(sim, 0, tilted.placement.translation, glm::vec3(0.0f)); // on the top face, phi = 0
    sim.substep();
    const glm::vec3 normal(-0.5f, std::sqrt(0.75f), 0.0f); // Rz(30 degrees) * (0, 1, 0)
    expectVecNear(sim.particles()[0].position, tilted.placement.translation + kRadius * normal,
                  1e-6f);
    EXPECT_EQ(sim.stats().insideColliders, 0u);
}

TEST(ReferencePbf, ScaledSphereColliderPushesAParticleOutToItsSurface) {
    static const format::ColliderAsset sphere =
        testscene::sphereColliderAsset(glm::dvec3(0.0), 0.1, 0.01);
    ref::ReferenceCollider c{&sphere, {}};
    c.placement.translation = {1.0f, 0.0f, 0.0f};
    c.placement.scale = 2.0f; // world radius 0.2
    format::Scene scene = oneParticleScene();
    scene.simulation.gravity = glm::vec3(0.0f);
    ref::ReferencePbf sim(scene, {c});
    // Local (0.075, 0.005, 0.005): a cell centre in y and z, where the trilinear gradient is
    // accurate to O(voxel^2) (on a grid plane it is one-sided and tilts by about 4 degrees).
    const glm::vec3 x0(1.15f, 0.01f, 0.01f);
    place(sim, 0, x0, glm::vec3(0.0f));
    const glm::vec3 radial = glm::normalize(x0 - c.placement.translation);
    EXPECT_NEAR(sim.colliderDistance(x0, 0.0f), glm::length(x0 - c.placement.translation) - 0.2f,
                1e-3f); // trilinear error
    sim.substep();
    expectVecNear(sim.particles()[0].position, c.placement.translation + (0.2f + kRadius) * radial,
                  5e-4f);
    EXPECT_EQ(sim.stats().insideColliders, 0u);
}

TEST(ReferencePbf, RisingPlatformLiftsAParticle) {
    ref::ReferenceCollider platform = floorCollider();
    platform.placement.linearVelocity = {0.0f, 0.5f, 0.0f};
    ref::ReferencePbf sim(oneParticleScene(), {platform});
    place(sim, 0, {0.0f, kRadius, 0.0f}, glm::vec3(0.0f));
    sim.substep(); // the platform's pose at the end of the substep counts
    EXPECT_NEAR(sim.particles()[0].position.y, kRadius + 0.5f * sim.constants().dt, 1e-6f);
    for (int s = 0; s < 30; ++s)
        sim.step();
    const rt::ParticleState& p = sim.particles()[0];
    EXPECT_NEAR(p.position.y, 0.5f * sim.time() + kRadius, 1e-4f);
    EXPECT_NEAR(p.velocity.y, 0.5f, 1e-3f);
    EXPECT_NEAR(p.position.x, 0.0f, 1e-6f);
}

TEST(ReferencePbf, MovingPlatformWithFullFrictionCarriesAParticle) {
    for (float friction : {0.0f, 1.0f}) {
        ref::ReferenceCollider platform = floorCollider(friction);
        platform.placement.linearVelocity = {0.3f, 0.0f, 0.0f};
        ref::ReferencePbf sim(oneParticleScene(), {platform});
        place(sim, 0, {0.0f, kRadius, 0.0f}, glm::vec3(0.0f));
        for (int s = 0; s < 30; ++s)
            sim.step();
        const rt::ParticleState& p = sim.particles()[0];
        EXPECT_NEAR(p.position.x, friction * 0.3f * sim.time(), 1e-5f);
        EXPECT_NEAR(p.velocity.x, friction * 0.3f, 1e-3f);
        EXPECT_NEAR(p.position.y, kRadius, 1e-6f);
    }
}

TEST(ReferencePbf, TurntableWithFullFrictionTurnsAParticleWithIt) {
    ref::ReferenceCollider table = floorCollider(1.0f);
    table.placement.angularVelocityDegrees = {0.0f, 90.0f, 0.0f};
    ref::ReferencePbf sim(oneParticleScene(), {table});
    place(sim, 0, {0.2f, kRadius, 0.0f}, glm::vec3(0.0f));
    for (int s = 0; s < 60; ++s) // 1 s: a quarter turn, (0.2, 0, 0) -> (0, 0, -0.2)
        sim.step();
    const rt::ParticleState& p = sim.particles()[0];
    // The contact-point rule drifts outward by (w dt)^2 r / 2 per substep, 1e-3 m in all.
    expectVecNear(p.position, {0.0f, kRadius, -0.2f}, 2e-3f);
    EXPECT_NEAR(glm::length(p.velocity), 0.2f * std::numbers::pi_v<float> / 2.0f, 5e-3f);
}

TEST(ReferencePbf, XsphBlendsTheVelocitiesOfNeighbours) {
    format::Scene scene = testscene::emptyScene(kSpacing, 4, 2);
    scene.simulation.gravity = glm::vec3(0.0f);
    scene.simulation.xsph = 0.5f;
    scene.simulation.vorticity = 0.0f;
    scene.simulation.scorrK = 0.0f;
    format::FluidBlock block;
    block.max = glm::vec3(2.0f * kSpacing, kSpacing, kSpacing);
    scene.blocks.push_back(block);
    ref::ReferencePbf sim(scene, {});
    place(sim, 0, {0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f});
    place(sim, 1, {0.03f, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f});
    sim.substep();
    const rt::PbfConstants& c = sim.constants();
    // Two particles are far below rest density: no correction, x* = x + dt v.
    const double q = 0.03 - 2.0 * c.dt;
    const double w = 315.0 / (64.0 * std::numbers::pi * std::pow(c.h, 9)) *
                     std::pow(double(c.h) * c.h - q * q, 3);
    const double expected = 1.0 + 0.5 * c.volume * (-2.0) * w;
    EXPECT_NEAR(sim.particles()[0].velocity.x, expected, 1e-4);
    EXPECT_NEAR(sim.particles()[1].velocity.x, -expected, 1e-4);
    EXPECT_LT(expected, 0.99); // the test sees XSPH at all
}

TEST(ReferencePbf, EmitterStopsAtCapacityAndReportsIt) {
    format::Scene scene = testscene::emptyScene(kSpacing, 4, 30);
    scene.simulation.gravity = glm::vec3(0.0f);
    format::Emitter e;
    e.position = {0.0f, 1.0f, 0.0f};
    e.radius = 0.04f; // 13 per layer
    e.speed = 1.0f;   // a layer every 0.02 s: at t = 0, 0.0208 (substep 5), 0.0417 (substep 10)
    e.stop = 1.0f;
    scene.emitters.push_back(e);
    ref::ReferencePbf sim(scene, {});
    sim.step();
    EXPECT_EQ(sim.particles().size(), 13u);
    EXPECT_FALSE(sim.stats().capacityReached);
    sim.step();
    EXPECT_EQ(sim.particles().size(), 26u);
    EXPECT_FALSE(sim.stats().capacityReached);
    sim.step();
    EXPECT_EQ(sim.particles().size(), 30u);
    EXPECT_TRUE(sim.stats().capacityReached);
    for (std::uint32_t i = 0; i < 30; ++i)
        EXPECT_EQ(sim.particles()[i].id, i);
    // The first layer left at t = 0 at 1 m/s and has moved for 3 steps.
    // (s_corr between the layers pushes it ahead a little.)
    EXPECT_NEAR(sim.particles()[6].position.y, 1.0f - sim.time(), 0.5f * kSpacing);
}

TEST(ReferencePbf, TargetDensityErrorEndsTheSolveAfterMinIterations) {
    format::Scene scene = testscene::smallScene({4, 4, 4}, kSpacing);
    scene.simulation.maxIterations = 8;
    {
        ref::ReferencePbf sim(scene, {});
        sim.substep();
        EXPECT_EQ(sim.stats().iterationsLastSubstep, 8u); // target 0: always all iterations
    }
    // A target every iteration meets: the stop at minIterations, after an even count only
    // (docs/pbf.md step 4.2).
    scene.simulation.targetDensityError = 0.5f;
    for (std::uint32_t minIterations : {0u, 2u, 5u}) {
        scene.simulation.minIterations = minIterations;
        ref::ReferencePbf sim(scene, {});
        sim.substep();
        EXPECT_EQ(sim.stats().iterationsLastSubstep, minIterations + minIterations % 2);
    }
}

namespace {

/// A dynamic box, the solid [-0.1, 0.1] x [-0.1, 0] x [-0.1, 0.1] (top face y = 0), placed by
/// `translation` and Euler `degrees`, its centre of mass at `centre` (the reference takes it as
/// given), no friction.
ref::ReferenceCollider bodyCollider(glm::vec3 translation, glm::vec3 degrees, glm::vec3 centre) {
    static const format::ColliderAsset asset =
        testscene::boxColliderAsset({-0.1, -0.1, -0.1}, {0.1, 0.0, 0.1}, 0.005);
    ref::ReferenceCollider c;
    c.asset = &asset;
    c.placement.asset = "body.sdf";
    c.placement.translation = translation;
    c.placement.rotationDegrees = degrees;
    c.placement.dynamic = format::DynamicBody{};
    c.centerOfMass = centre;
    return c;
}

} // namespace

// The lone particle is far from the domain's walls; the body's fluid-facing surface lies 0.05
// spacings inside phi = 0 (docs/bodies.md, "Surface offset").
TEST(ReferencePbf, ABodyPushesALoneParticleOutToItsFluidFacingSurfaceAndTakesTheReaction) {
    format::Scene scene = oneParticleScene();
    const float offset = 0.05f * kSpacing;
    scene.simulation.gravity = glm::vec3(0.0f);
    scene.simulation.minIterations = 1;
    scene.simulation.maxIterations = 1;
    // Tilted 20 degrees about z: the top face's world normal is n = (-sin 20, cos 20, 0).
    const glm::vec3 centre(0.3f, 0.45f, 0.2f);
    ref::ReferencePbf sim(scene, {bodyCollider({0.3f, 0.5f, 0.2f}, {0.0f, 0.0f, 20.0f}, centre)});
    ASSERT_EQ(sim.bodyCount(), 1u);
    EXPECT_EQ(sim.particlesRemovedAtSpawn(), 0u);
    const float angle = glm::radians(20.0f);
    const glm::vec3 n(-std::sin(angle), std::cos(angle), 0.0f);
    const glm::vec3 across(std::cos(angle), std::sin(angle), 0.0f);
    // 1.5 spacings under the top face: deep enough that the boundary volume alone (about 0.87
    // of the support) with the particle's own W(0) compresses it, so lambda pushes it first.
    const glm::vec3 x0 =
        glm::vec3(0.3f, 0.5f, 0.2f) + 0.02f * across + glm::vec3(0, 0, 0.03f) - 1.5f * kSpacing * n;
    place(sim, 0, x0, glm::vec3(0.0f));
    sim.substep();
    EXPECT_GT(sim.stats().maxDensityError, 0.01);
    const glm::vec3 x1 = sim.particles()[0].position;
    // Out along n to r from the fluid-facing surface, the offset inside the zero level set.
    EXPECT_NEAR(sim.colliderDistance(x1, sim.time()), kRadius - offset, 1e-6f);
    EXPECT_LT(glm::length(glm::cross(x1 - x0, n)), 1e-6f);
    // The body takes -m dx / dt^2 about its centre of mass (both corrections lie along n, so
    // their moments add up to (x0 - c) x F).
    const double m = sim.constants().mass, dt = sim.constants().dt;
    const glm::dvec3 force = -m * glm::dvec3(x1 - x0) / (dt * dt);
    const glm::dvec3 torque = glm::cross(glm::dvec3(x0) - glm::dvec3(centre), force);
    EXPECT_LT(glm::length(sim.bodyForce(0) - force), 1e-5 * glm::length(force));
    EXPECT_LT(glm::length(sim.bodyTorque(0) - torque), 1e-5 * glm::length(torque));
    EXPECT_GT(glm::length(torque), 0.02 * glm::length(force)); // a lever of a few cm
}

TEST(ReferencePbf, ABodyLeavesOutTheParticlesItStartsOnAndTakesTheWatersMomentumChange) {
    // Weightless water, no walls, no confinement: the fluid's own corrections and XSPH conserve
    // momentum, so what the water gains over a step is what its body gave it, -F dt.
    format::Scene scene = testscene::emptyScene(kSpacing, 4, 512);
    scene.simulation.gravity = glm::vec3(0.0f);
    scene.simulation.vorticity = 0.0f;
    format::FluidBlock block;
    block.max = glm::vec3(8.0f * kSpacing);
    scene.blocks.push_back(block);
    // The tilted box fills the block's corner at the origin, up to about 3.3 spacings.
    const glm::vec3 centre(0.0f, -0.03f, 0.02f);
    ref::ReferencePbf sim(scene,
                          {bodyCollider({0.0f, 0.066f, 0.0f}, {10.0f, 0.0f, 15.0f}, centre)});
    const std::uint32_t removed = sim.particlesRemovedAtSpawn();
    EXPECT_GT(removed, 40u);
    EXPECT_LT(removed, 300u);
    ASSERT_EQ(sim.particles().size(), 512u - removed);
    std::uint32_t previous = 0;
    for (const rt::ParticleState& p : sim.particles()) {
        EXPECT_GE(sim.colliderDistance(p.position, 0.0f), 0.0f) << "id " << p.id;
        EXPECT_TRUE(p.id == 0 || p.id > previous) << "ids keep the blocks' numbering, in order";
        previous = p.id;
    }
    EXPECT_EQ(sim.particles().back().id, 511u);

    sim.step();
    glm::dvec3 momentum(0.0);
    for (const rt::ParticleState& p : sim.particles())
        momentum += double(sim.constants().mass) * glm::dvec3(p.velocity);
    const glm::dvec3 impulse = sim.bodyForce(0) * double(scene.simulation.timeStep);
    EXPECT_GT(glm::length(impulse), 1e-4); // [N s]: the body pushed
    EXPECT_LT(glm::length(momentum + impulse), 1e-4 * glm::length(impulse));
}
