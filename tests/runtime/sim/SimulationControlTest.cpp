// The calls a game loop makes between steps (docs/embedding.md): a scene built from default
// parameters, collider poses set each frame, particles added, emitters switched without a burst,
// the fixed-step driver and the view of the buffers. Removal is SimulationRemovalTest.cpp, the
// GL contract and the reads without a wait SimulationGlContractTest.cpp.
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "sim/ParticleCompare.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;

class SimulationControl : public GpuTest {};

using test::particleBytes;

// ---------------------------------------------------------------------------------------------
// Parameters a program builds

TEST_F(SimulationControl, DefaultParametersPlayAsTheFileDefaultsDo) {
    format::Scene scene;
    scene.path = "game";
    format::FluidBlock block;
    block.max = glm::vec3(0.12f, 0.08f, 0.12f);
    scene.blocks.push_back(block);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(0.12f, 0.24f, 0.12f);
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    const format::SimulationParams& p = sim->parameters();
    EXPECT_FLOAT_EQ(p.kernelRadius, 0.04f);
    EXPECT_FLOAT_EQ(p.scorrDeltaQ, 0.008f);
    EXPECT_GT(p.vorticity, 0.0f);
    EXPECT_GE(p.substeps, 1u);
    EXPECT_EQ(p.capacity, 6u * 4u * 6u);
    EXPECT_EQ(sim->particleCount(), p.capacity);
    for (int i = 0; i < 5; ++i)
        sim->step();
    const StepStats stats = sim->readStats();
    EXPECT_EQ(stats.nonFinite, 0u);
    EXPECT_LT(stats.maxDensityError, 0.5);
    EXPECT_LT(stats.maxSpeed, 2.0);
}

TEST_F(SimulationControl, CreateReturnsAnErrorForBadParametersInsteadOfAborting) {
    format::Scene scene = testscene::smallScene({4, 4, 4});
    struct Bad {
        void (*edit)(format::SimulationParams&);
        ErrorCode code;
        const char* message;
    };
    const Bad bads[] = {
        {[](format::SimulationParams& p) { p.spacing = 0.0f; }, ErrorCode::InvalidArgument,
         "simulation.spacing"},
        {[](format::SimulationParams& p) { p.timeStep = std::nanf(""); }, ErrorCode::NonFinite,
         "simulation.timeStep"},
        {[](format::SimulationParams& p) { p.maxIterations = 0; }, ErrorCode::InvalidArgument,
         "maxIterations"},
        {[](format::SimulationParams& p) { p.capacity = 10; }, ErrorCode::InvalidArgument,
         "simulation.capacity: 10 is smaller than the 64 particles"},
    };
    for (const Bad& bad : bads) {
        format::Scene edited = scene;
        bad.edit(edited.simulation);
        auto sim = Simulation::create(edited, {});
        ASSERT_FALSE(sim);
        EXPECT_EQ(sim.error().code, bad.code);
        EXPECT_NE(sim.error().detail.find(bad.message), std::string::npos) << sim.error().detail;
    }
}

// ---------------------------------------------------------------------------------------------
// Collider poses set by the program

// A pool 8 x 6 x 8 particles deep with a paddle (a 4 x 10 x 10 cm box) standing in it.
format::Scene paddleScene(std::vector<format::ColliderAsset>& assets) {
    format::Scene scene = testscene::smallScene({8, 6, 8}, 0.02f, 2);
    assets.push_back(testscene::boxColliderAsset({-0.02, -0.05, -0.05}, {0.02, 0.05, 0.05}, 0.01));
    format::SceneCollider paddle;
    paddle.asset = "paddle.slc";
    paddle.friction = 0.2f;
    scene.colliders.push_back(paddle);
    return scene;
}

// Where the paddle is at the end of step n: sweeping along x and turning about y.
format::ColliderKey paddleKey(int n, float stepTime) {
    return {stepTime * float(n), glm::vec3(0.04f + 0.012f * float(n), 0.06f, 0.08f),
            glm::vec3(0.0f, 6.0f * float(n), 0.0f)};
}

TEST_F(SimulationControl, PosesSetEachStepPushWaterBitForBitAsTheSameKeyframesDo) {
    constexpr int kSteps = 6;
    std::vector<format::ColliderAsset> assets;
    const format::Scene base = paddleScene(assets);
    const PbfConstants k = deriveConstants(base.simulation);
    // Key times on the simulation's own clock: substeps of k.dt summed in double.
    std::vector<format::ColliderKey> keys;
    for (int n = 0; n <= kSteps; ++n) {
        format::ColliderKey key = paddleKey(n, 0.0f);
        key.time = float(double(k.dt) * double(base.simulation.substeps) * n);
        keys.push_back(key);
    }
    SimulationOptions options;
    options.deterministic = true;

    format::Scene keyed = base;
    keyed.colliders[0].keys = keys;
    auto a = Simulation::create(keyed, assets, options);
    ASSERT_TRUE(a) << a.error().message();

    format::Scene driven = base;
    driven.colliders[0].translation = keys[0].translation;
    driven.colliders[0].rotationDegrees = keys[0].rotationDegrees;
    auto b = Simulation::create(driven, assets, options);
    ASSERT_TRUE(b) << b.error().message();
    auto still = Simulation::create(driven, assets, options);
    ASSERT_TRUE(still) << still.error().message();

    for (int n = 1; n <= kSteps; ++n) {
        ASSERT_TRUE(
            b->setColliderPose(0, keys[n].translation, eulerDegrees(keys[n].rotationDegrees)));
        a->step();
        b->step();
        still->step();
        const ColliderPose pa = a->colliderPoses()[0];
        const ColliderPose pb = b->colliderPoses()[0];
        EXPECT_EQ(pa.translation, pb.translation) << "step " << n;
        EXPECT_EQ(pa.rotation, pb.rotation) << "step " << n;
    }
    const std::vector<ParticleState> pa = a->downloadParticles();
    EXPECT_TRUE(particleBytes(pa) == particleBytes(b->downloadParticles()))
        << "the set poses moved the water differently from the keyframes";
    // The paddle did push: the water differs from a run where it stood still.
    EXPECT_GT(test::maxPositionDifference(pa, still->downloadParticles()), 2e-3);
    EXPECT_EQ(b->colliderPoses()[0].translation, keys[kSteps].translation);
}

TEST_F(SimulationControl, SetColliderPoseRefusesBadInputAndChangesNothing) {
    std::vector<format::ColliderAsset> assets;
    format::Scene scene = paddleScene(assets);
    scene.colliders[0].translation = glm::vec3(0.04f, 0.06f, 0.08f);
    auto sim = Simulation::create(scene, assets);
    ASSERT_TRUE(sim) << sim.error().message();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const glm::quat unit(1.0f, 0.0f, 0.0f, 0.0f);
    auto out = sim->setColliderPose(1, glm::vec3(0.1f), unit);
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    out = sim->setColliderPose(0, glm::vec3(0.1f, nan, 0.1f), unit);
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::NonFinite);
    out = sim->setColliderPose(0, glm::vec3(0.1f), glm::quat(nan, 0.0f, 0.0f, 0.0f));
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::NonFinite);
    out = sim->setColliderPose(0, glm::vec3(0.1f), glm::quat(0.0f, 0.0f, 0.0f, 0.0f));
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    sim->step();
    EXPECT_EQ(sim->colliderPoses()[0].translation, scene.colliders[0].translation);
    // A quaternion that is not unit is normalised.
    ASSERT_TRUE(
        sim->setColliderPose(0, glm::vec3(0.05f, 0.06f, 0.08f), glm::quat(2.0f, 0.0f, 0.0f, 0.0f)));
    sim->step();
    EXPECT_FLOAT_EQ(sim->colliderPoses()[0].rotation.w, 1.0f);
    EXPECT_EQ(sim->colliderPoses()[0].translation, glm::vec3(0.05f, 0.06f, 0.08f));
}

// ---------------------------------------------------------------------------------------------
// Particles the program adds

TEST_F(SimulationControl, AddedParticlesGetNewIdsAndLeaveTheOthersAsTheyWere) {
    format::Scene scene = testscene::smallScene({6, 4, 6}, 0.02f, 2);
    const std::uint32_t blockParticles = scene.simulation.capacity;
    scene.simulation.capacity = blockParticles + 64;
    scene.domainMax = glm::vec3(0.48f, 0.16f, 0.12f); // room far from the block along x
    SimulationOptions options;
    options.deterministic = true;
    auto plain = Simulation::create(scene, {}, options);
    auto added = Simulation::create(scene, {}, options);
    ASSERT_TRUE(plain && added);
    plain->step();
    added->step();
    // A 4 x 2 x 4 block in the air more than 2 h from the water, falling at 0.5 m/s.
    std::vector<glm::vec3> positions, velocities;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 2; ++j)
            for (int l = 0; l < 4; ++l) {
                positions.emplace_back(0.39f + 0.02f * i, 0.09f + 0.02f * j, 0.03f + 0.02f * l);
                velocities.emplace_back(0.0f, -0.5f, 0.0f);
            }
    auto first = added->addParticles(positions, velocities);
    ASSERT_TRUE(first) << first.error().message();
    EXPECT_EQ(*first, blockParticles);
    EXPECT_EQ(added->particleCount(), blockParticles + 32);
    for (int i = 0; i < 3; ++i) {
        plain->step();
        added->step();
    }
    const auto before = test::byId(plain->downloadParticles());
    const auto after = test::byId(added->downloadParticles());
    ASSERT_EQ(after.size(), blockParticles + 32u);
    for (std::uint32_t id = 0; id < blockParticles; ++id) {
        ASSERT_TRUE(after.count(id)) << "id " << id;
        EXPECT_EQ(after.at(id).position, before.at(id).position) << "id " << id;
    }
    // 3 steps (0.05 s) from 0.5 m/s: 3.7 cm down, on the floor at 1 cm at the lowest, where the
    // little block spreads sideways by less than a spacing.
    glm::dvec3 centre(0.0);
    for (std::uint32_t id = blockParticles; id < blockParticles + 32; ++id) {
        ASSERT_TRUE(after.count(id)) << "id " << id;
        const glm::vec3 start = positions[id - blockParticles];
        centre += glm::dvec3(after.at(id).position) / 32.0;
        EXPECT_NEAR(after.at(id).position.x, start.x, 0.02) << "id " << id;
        EXPECT_LT(after.at(id).position.y, start.y - 0.02f) << "id " << id;
        EXPECT_GT(after.at(id).position.y, start.y - 0.06f) << "id " << id;
    }
    EXPECT_NEAR(centre.x, 0.42, 2e-3);
    EXPECT_NEAR(centre.z, 0.06, 2e-3);
}

TEST_F(SimulationControl, AddParticlesRefusesBadInputAndChangesNothing) {
    format::Scene scene = testscene::smallScene({4, 4, 4});
    scene.simulation.capacity = 70;
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    const std::vector<glm::vec3> seven(7, glm::vec3(0.02f, 0.1f, 0.02f));
    auto out = sim->addParticles(seven);
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(out.error().detail.find("64 of the capacity 70"), std::string::npos);
    out = sim->addParticles({glm::vec3(0.02f)}, {glm::vec3(0.0f), glm::vec3(0.0f)});
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    out = sim->addParticles({glm::vec3(0.02f), glm::vec3(std::numeric_limits<float>::infinity())});
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::NonFinite);
    EXPECT_EQ(sim->particleCount(), 64u);
    const std::vector<glm::vec3> six(6, glm::vec3(0.02f, 0.1f, 0.02f));
    out = sim->addParticles(six);
    ASSERT_TRUE(out) << out.error().message();
    EXPECT_EQ(*out, 64u);
    EXPECT_EQ(sim->particleCount(), 70u);
}

// ---------------------------------------------------------------------------------------------
// Emitters, the driver, the view

TEST_F(SimulationControl, EmittersSwitchedBackOnDoNotReleaseTheLayersDueWhileOff) {
    const format::Scene scene = testscene::nozzleScene(4000);
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    sim->step();
    sim->step();
    const std::uint32_t twoSteps = sim->particleCount();
    ASSERT_GT(twoSteps, 0u);
    sim->setEmittersEnabled(false);
    for (int i = 0; i < 15; ++i) // 0.25 s: about 12 layers fall due
        sim->step();
    EXPECT_EQ(sim->particleCount(), twoSteps);
    sim->setEmittersEnabled(true);
    sim->step();
    const std::uint32_t disc = std::uint32_t(emitterDisc(scene.emitters[0], 0.02f).size());
    // One step of 1/60 s at 1 m/s owes at most one layer of 2 cm, or two where it starts one.
    EXPECT_GT(sim->particleCount(), twoSteps);
    EXPECT_LE(sim->particleCount(), twoSteps + 2 * disc);
}

TEST_F(SimulationControl, AdvanceStepsWholeStepsAndCarriesTheRest) {
    auto sim = Simulation::create(testscene::smallScene({4, 4, 4}), {});
    ASSERT_TRUE(sim) << sim.error().message();
    const double dt = sim->parameters().timeStep;
    for (int frame = 0; frame < 3; ++frame) {
        auto a = sim->advance(dt);
        ASSERT_TRUE(a);
        EXPECT_EQ(a->steps, 1u);
        EXPECT_LT(a->remainder, 1e-9);
    }
    auto half = sim->advance(0.5 * dt);
    ASSERT_TRUE(half);
    EXPECT_EQ(half->steps, 0u);
    EXPECT_NEAR(half->alpha, 0.5, 1e-6);
    EXPECT_NEAR(half->remainder, 0.5 * dt, 1e-9);
    auto rest = sim->advance(0.75 * dt);
    ASSERT_TRUE(rest);
    EXPECT_EQ(rest->steps, 1u);
    EXPECT_NEAR(rest->alpha, 0.25, 1e-6);
    EXPECT_EQ(sim->steps(), 4u);
    // A frame owing 60 steps takes maxSteps and drops the rest.
    auto slow = sim->advance(1.0, 3);
    ASSERT_TRUE(slow);
    EXPECT_EQ(slow->steps, 3u);
    EXPECT_NEAR(slow->dropped + 3.0 * dt + slow->remainder, 1.0 + 0.25 * dt, 1e-9);
    EXPECT_LT(slow->remainder, dt);
    EXPECT_EQ(sim->steps(), 7u);
    // Frames of 1/60 s in double at the float step 1/60 s (4e-8 of a step longer) step once each.
    for (int frame = 0; frame < 3; ++frame) {
        auto a = sim->advance(1.0 / 60.0);
        ASSERT_TRUE(a);
        EXPECT_EQ(a->steps, 1u);
    }
    EXPECT_EQ(sim->steps(), 10u);
    for (double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
        auto out = sim->advance(bad);
        ASSERT_FALSE(out);
        EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    }
    EXPECT_FALSE(sim->advance(dt, 0));
    EXPECT_EQ(sim->steps(), 10u);
}

TEST_F(SimulationControl, ParticleViewNamesTheBuffersAndTheIdsOfTheSlots) {
    auto sim = Simulation::create(testscene::smallScene({4, 4, 4}, 0.02f, 3), {});
    ASSERT_TRUE(sim) << sim.error().message();
    for (int i = 0; i < 2; ++i) {
        sim->step();
        const ParticleView view = sim->particleView();
        EXPECT_EQ(view.count, sim->particleCount());
        EXPECT_EQ(view.positions, sim->positionBuffer().id());
        EXPECT_EQ(view.velocities, sim->velocityBuffer().id());
        std::vector<glm::vec4> positions(view.count);
        std::vector<std::uint32_t> ids(view.count);
        glGetNamedBufferSubData(view.positions, 0, GLsizeiptr(view.count * view.positionStride),
                                positions.data());
        glGetNamedBufferSubData(view.ids, 0, GLsizeiptr(view.count * view.idStride), ids.data());
        const std::vector<ParticleState> particles = sim->downloadParticles();
        ASSERT_EQ(particles.size(), view.count);
        for (std::uint32_t slot = 0; slot < view.count; ++slot) {
            EXPECT_EQ(ids[slot], particles[slot].id);
            EXPECT_EQ(glm::vec3(positions[slot]), particles[slot].position);
        }
    }
}

} // namespace
} // namespace sluice::rt
