// Dynamic bodies in the GPU solver (docs/bodies.md): Archimedes' draft, sinking and rising,
// momentum exchange, contacts, robustness and determinism, on llvmpipe-sized scenes. Bodies
// released in deep water or resting on the floor are in BodyReleaseTest.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "bodies/BodyTank.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;
using namespace bodytest;

class SimulationBodies : public GpuTest {};

struct Settled {
    double share = 0.0; ///< submerged share, mean of six frames over the last second
    double verticalRms =
        0.0; ///< rms vertical speed of the body's frames over the last second [m/s]
    BodyState body;
    Health health;
    bool bodyFinite = true;
};

constexpr glm::vec2 kTank(0.4f, 0.4f);
constexpr float kDepth = 0.2f;

// A cube of side `side` at `ratio` times the water's density, its centre at height `y` in the
// middle of the tank, played for `seconds`. Deterministic: without a fixed particle order the
// water's arrangement, and with it the settled draft, differs from run to run by a few
// hundredths (0.523 to 0.551 at ratio 0.5 in four runs), so a run could land either side of
// a limit; with it every run gives the same figures.
Settled playCube(float ratio, float side, float y, float seconds) {
    format::Scene scene = tankScene(kTank, kDepth, 0.5f);
    scene.colliders.push_back(cubeBody(glm::vec3(0.5f * kTank.x, y, 0.5f * kTank.y), ratio));
    std::vector<format::ColliderAsset> assets{cubeAsset(side)};
    SimulationOptions options;
    options.deterministic = true;
    auto sim = Simulation::create(scene, std::move(assets), options);
    EXPECT_TRUE(sim) << sim.error().message();
    if (!sim)
        return {};
    Settled out;
    const int steps = int(std::lround(60 * seconds));
    double squares = 0.0;
    int counted = 0;
    double shares = 0.0, lastLevel = 0.0;
    int shareSamples = 0;
    float previousY = sim->bodies().at(0).position.y;
    for (int step = 1; step <= steps; ++step) {
        sim->step();
        out.health.add(sim->readStats());
        const BodyState body = sim->bodies().at(0);
        out.bodyFinite = out.bodyFinite && finite(body);
        // The vertical velocity of each frame: the centre's rise over the step, per second.
        // (BodyState::linearVelocity is the last substep's, which carries the solver's
        // substep-to-substep jitter of a few tenths of a millimetre.)
        const double frameVelocity = double(body.position.y - previousY) * 60.0;
        previousY = body.position.y;
        if (step > steps - 60) {
            squares += frameVelocity * frameVelocity;
            ++counted;
            // The share over the last second, every 10th frame: the water still sloshes a
            // little, and one frame's level carries its wave.
            if (step % 10 == 0) {
                const double level =
                    waterLevel(sim->downloadParticles(), body.position, 0.6 * side, kTank,
                               sim->constants().volume, lowestPoint(body, side));
                shares += submergedShare(body, side, level);
                ++shareSamples;
                lastLevel = level;
            }
        }
    }
    out.body = sim->bodies().at(0);
    const double level = lastLevel;
    out.share = shares / std::max(shareSamples, 1);
    out.verticalRms = std::sqrt(squares / std::max(counted, 1));
    std::printf("cube at %.2f x water density: submerged share %.3f (surface %.4f m), vertical "
                "rms %.4f m/s over the last second, centre at %.4f m, %u contacts\n",
                ratio, out.share, level, out.verticalRms, out.body.position.y, out.body.contacts);
    return out;
}

void expectHealthy(const Settled& s) {
    EXPECT_EQ(s.health.nonFinite, 0u);
    EXPECT_EQ(s.health.inside, 0u);
    EXPECT_TRUE(s.bodyFinite);
}

// Start with the cube 0.1 of its height higher than Archimedes' draft, so it has to settle.
float startHeight(float ratio) {
    return kDepth + kSide * (0.5f - (ratio - 0.1f));
}

// A cube released 0.1 of its height above its draft settles at Archimedes' draft, at rest,
// touching nothing.
void expectFloatsAtTheDraft(float ratio) {
    const Settled s = playCube(ratio, kSide, startHeight(ratio), 3.0f);
    EXPECT_NEAR(s.share, ratio, 0.05) << "density ratio " << ratio;
    EXPECT_LT(s.verticalRms, 0.02) << "density ratio " << ratio;
    EXPECT_EQ(s.body.contacts, 0u) << "a floating cube touches nothing";
    expectHealthy(s);
}

TEST_F(SimulationBodies, CubesFloatAtTheDraftArchimedesGivesAtAQuarter) {
    expectFloatsAtTheDraft(0.25f);
}

TEST_F(SimulationBodies, CubesFloatAtTheDraftArchimedesGivesAtAHalf) {
    expectFloatsAtTheDraft(0.5f);
}

TEST_F(SimulationBodies, CubesFloatAtTheDraftArchimedesGivesAtThreeQuarters) {
    expectFloatsAtTheDraft(0.75f);
}

TEST_F(SimulationBodies, ABodyATenthLighterThanWaterFloatsAndOneATenthHeavierSinks) {
    // Both are released with their top level with the water's surface, all of them under water:
    // the lighter one must stay up with part of it out of the water, the heavier one must sink.
    const float start = kDepth - 0.5f * kSide;
    const Settled light = playCube(0.9f, kSide, start, 2.5f);
    EXPECT_LT(light.share, 0.95) << "ratio 0.9 must keep part of itself out of the water";
    EXPECT_GT(light.share, 0.75);
    EXPECT_EQ(light.body.contacts, 0u) << "it floats, touching nothing";
    const Settled heavy = playCube(1.1f, kSide, start, 4.0f);
    EXPECT_GT(heavy.share, 0.99) << "ratio 1.1 must stay under water";
    EXPECT_LT(heavy.body.position.y, start - 0.02f) << "it must have sunk";
    expectHealthy(light);
    expectHealthy(heavy);
}

TEST_F(SimulationBodies, AHeavyBodySinksToTheFloorWithoutSinkingIntoIt) {
    // Released under water, its bottom half way down to the floor. It comes to rest on the
    // floor or on the last layer of water it traps there (docs/bodies.md, "Known limits").
    const Settled s = playCube(2.0f, kSide, 0.5f * kSide + 0.5f * (kDepth - kSide), 2.5f);
    const double lowest = lowestPoint(s.body, kSide);
    EXPECT_GT(lowest, -0.5 * kSpacing) << "penetration of the floor";
    EXPECT_LT(lowest, kSpacing) << "at most one water layer under it";
    EXPECT_LT(s.body.contactDepth, 0.5 * kSpacing);
    EXPECT_LT(s.verticalRms, 0.02);
    expectHealthy(s);
}

TEST_F(SimulationBodies, ALightBodyReleasedLowInTheWaterRisesToTheSurface) {
    // Under water from the start, one water layer under it: its lowest face 1.5 spacings above
    // the floor where the walls hold bodies, so one layer of particle centres fits below it.
    const float start = 0.5f * kSide + 1.5f * kSpacing;
    ASSERT_LT(start + 0.5f * kSide, kDepth) << "released with its top under water";
    const Settled s = playCube(0.5f, kSide, start, 3.0f);
    EXPECT_GT(s.body.position.y, start + 0.05f) << "it must have risen";
    EXPECT_LT(s.share, 0.7) << "and float with part of it out of the water";
    EXPECT_EQ(s.body.contacts, 0u);
    expectHealthy(s);
}

TEST_F(SimulationBodies, ABodyHeavierThanWaterReleasedLowDoesNotRise) {
    // The same heights for a cube a tenth heavier than water: whatever lifts the light one must
    // be buoyancy. Released half a spacing up, the floor layer of particles sits against its
    // lower face; the walls put back what the cube pushes into them, and it takes only the part
    // of that reaction which stops it (docs/bodies.md, "Particles held against a wall"). Before
    // that rule it rose to 0.115 m here, lifted a little by every held particle in every
    // iteration.
    for (float gap : {0.5f, 1.5f}) {
        const float start = 0.5f * kSide + gap * kSpacing;
        const Settled s = playCube(1.1f, kSide, start, 2.5f);
        EXPECT_LT(s.body.position.y, start + 0.1f * kSpacing) << "released " << gap << " up";
        EXPECT_GT(lowestPoint(s.body, kSide), -0.5 * kSpacing) << "released " << gap << " up";
        expectHealthy(s);
    }
}

glm::dvec3 fluidMomentum(const std::vector<ParticleState>& particles, double mass) {
    glm::dvec3 sum(0.0);
    for (const ParticleState& p : particles)
        sum += glm::dvec3(p.velocity);
    return sum * mass;
}

// Weightless water: a ball at rest in open space (no walls, no gravity) and a cube flying into
// it. Nothing outside the pair can push, so their total momentum must stay what it was.
format::Scene collisionScene(std::uint32_t substeps) {
    format::Scene scene;
    scene.path = "momentum.json";
    scene.name = "momentum";
    format::FluidBlock ball;
    ball.shape = format::FluidBlock::Shape::Sphere;
    ball.center = glm::vec3(0.0f);
    ball.radius = 0.12f;
    scene.blocks.push_back(ball);
    scene.simulation = testscene::defaultParams(kSpacing, substeps, 8000);
    scene.simulation.gravity = glm::vec3(0.0f);
    scene.simulation.vorticity = 0.0f; // confinement adds momentum by design
    format::SceneCollider cube = cubeBody(glm::vec3(-0.25f, 0.0f, 0.0f), 0.5f);
    // 0.4 m/s: a third of a spacing a substep, so the cube never overruns a particle.
    cube.dynamic->linearVelocity = glm::vec3(0.4f, 0.0f, 0.0f);
    scene.colliders.push_back(cube);
    return scene;
}

TEST_F(SimulationBodies, TheBodyAndTheWaterExchangeEqualAndOppositeImpulses) {
    format::Scene scene = collisionScene(1);
    auto sim = Simulation::create(scene, {cubeAsset(kSide)});
    ASSERT_TRUE(sim) << sim.error().message();
    const double m = sim->constants().mass;
    glm::dvec3 fluid = fluidMomentum(sim->downloadParticles(), m);
    BodyState body = sim->bodies().at(0);
    glm::dvec3 bodyMomentum = body.mass * glm::dvec3(body.linearVelocity);
    const glm::dvec3 start = fluid + bodyMomentum;
    int substepsWithContact = 0;
    int substepsPlayed = 0;
    Health health;
    for (int step = 1; step <= 60; ++step) { // 1 s, one substep per step
        sim->step();
        health.add(sim->readStats());
        const glm::dvec3 fluidNow = fluidMomentum(sim->downloadParticles(), m);
        ++substepsPlayed;
        body = sim->bodies().at(0);
        const glm::dvec3 bodyNow = body.mass * glm::dvec3(body.linearVelocity);
        const glm::dvec3 bodyImpulse = bodyNow - bodyMomentum;
        const glm::dvec3 fluidImpulse = fluidNow - fluid;
        // The fluid's momentum is read from float velocities v = (x* - x) / dt, each off by
        // up to an ulp of its position over dt: summed over N particles at random, about
        // m sqrt(N) ulp(|x|max) / dt (8 of those are the floor here). The body's impulse is the
        // particles' by construction (fixed-point sums, 2^-28 h a correction); what this test can
        // see of that is 1e-4 of the impulse above that floor. (The CPU reference, in double, shows
        // it to 5e-6: BodyParity and ReferencePbfTest.)
        const std::vector<ParticleState> particles = sim->downloadParticles();
        float reach = 0.0f;
        for (const ParticleState& p : particles)
            reach = std::max(reach, glm::length(p.position));
        const double floor = 8.0 * m * std::sqrt(double(particles.size())) *
                             double(std::nextafter(reach, 1e30f) - reach) /
                             double(sim->constants().dt);
        if (glm::length(bodyImpulse) > 100.0 * floor) {
            ++substepsWithContact;
            EXPECT_LT(glm::length(bodyImpulse + fluidImpulse),
                      1e-4 * glm::length(bodyImpulse) + floor)
                << "step " << step << ": body impulse " << bodyImpulse.x << ", fluid impulse "
                << fluidImpulse.x << ", float floor " << floor;
        }
        fluid = fluidNow;
        bodyMomentum = bodyNow;
    }
    const glm::dvec3 end = fluid + bodyMomentum;
    std::printf("momentum: start %.6f, end %.6f kg m/s (x); body at %.4f m/s after 1 s; %d "
                "substeps with contact\n",
                start.x, end.x, body.linearVelocity.x, substepsWithContact);
    EXPECT_GT(substepsWithContact, 20) << "the cube must plough into the water";
    EXPECT_EQ(substepsPlayed, 60);
    EXPECT_LT(body.linearVelocity.x, 0.36f) << "the water must slow the cube down";
    EXPECT_LT(glm::length(end - start), 0.01 * glm::length(start));
    EXPECT_EQ(health.nonFinite, 0u);
    EXPECT_EQ(health.inside, 0u);
}

TEST_F(SimulationBodies, ThreeStackedBoxesStayPutOnTheFloor) {
    format::Scene scene = testscene::emptyScene(kSpacing, 8, 16);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(0.4f, 0.5f, 0.4f);
    for (int i = 0; i < 3; ++i)
        scene.colliders.push_back(cubeBody(glm::vec3(0.2f, (0.5f + float(i)) * kSide, 0.2f), 0.8f));
    std::vector<format::ColliderAsset> assets(3, cubeAsset(kSide));
    auto sim = Simulation::create(scene, std::move(assets));
    ASSERT_TRUE(sim) << sim.error().message();
    for (int step = 0; step < 30; ++step) // settle for 0.5 s
        sim->step();
    const std::vector<BodyState> settled = sim->bodies();
    double worstSpeed = 0.0;
    for (int step = 0; step < 300; ++step) { // then 5 s
        sim->step();
        for (const BodyState& b : sim->bodies())
            worstSpeed = std::max(worstSpeed, double(glm::length(b.linearVelocity)));
    }
    const std::vector<BodyState> end = sim->bodies();
    for (int i = 0; i < 3; ++i) {
        const double drift = glm::length(end[i].position - settled[i].position) / 5.0;
        std::printf("box %d: centre %.5f m, drift %.5f m/s over 5 s, %u contacts\n", i,
                    end[i].position.y, drift, end[i].contacts);
        EXPECT_LT(drift, 1e-3) << "box " << i;
        EXPECT_NEAR(end[i].position.y, (0.5 + i) * kSide, 0.5 * kSpacing) << "box " << i;
        EXPECT_TRUE(finite(end[i]));
    }
    std::printf("stack: worst speed %.5f m/s\n", worstSpeed);
}

// Three boxes stacked on the floor and a fourth resting on a static box beside them, played
// for `steps` with the body pass's work group at `groupSize` invocations.
std::vector<BodyState> playContacts(std::uint32_t groupSize, int steps) {
    format::Scene scene = testscene::emptyScene(kSpacing, 8, 16);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(0.6f, 0.5f, 0.4f);
    for (int i = 0; i < 3; ++i)
        scene.colliders.push_back(cubeBody(glm::vec3(0.2f, (0.5f + float(i)) * kSide, 0.2f), 0.8f));
    addPedestalAndTiltedBox(scene);
    std::vector<format::ColliderAsset> assets(5, cubeAsset(kSide));
    SimulationOptions options;
    options.bodyGroupSize = groupSize;
    auto sim = Simulation::create(scene, std::move(assets), options);
    EXPECT_TRUE(sim) << sim.error().message();
    if (!sim)
        return {};
    for (int step = 0; step < steps; ++step)
        sim->step();
    return sim->bodies();
}

TEST_F(SimulationBodies, TheGpuWorkGroupLayoutGivesTheSameContactsAsTheSoftwareOne) {
    // Each body's contact points are split over its work group's invocations and their
    // corrections summed in a tree: 8 lanes on llvmpipe, up to 512 on a GPU. Same physics, sums
    // in another order: after 0.5 s of settling, the poses agree to a small fraction of a
    // spacing.
    const std::vector<BodyState> software = playContacts(8, 30);
    const std::vector<BodyState> gpu = playContacts(512, 30);
    ASSERT_EQ(software.size(), 4u);
    ASSERT_EQ(gpu.size(), 4u);
    for (std::size_t i = 0; i < software.size(); ++i) {
        const double apart = glm::length(glm::dvec3(software[i].position - gpu[i].position));
        const double turned =
            std::abs(glm::dot(glm::dquat(software[i].orientation), glm::dquat(gpu[i].orientation)));
        std::printf(
            "body %zu: centre %.5f / %.5f m, %.2e m apart, |q.q'| = %.9f, contacts %u / %u\n", i,
            software[i].position.y, gpu[i].position.y, apart, turned, software[i].contacts,
            gpu[i].contacts);
        EXPECT_LT(apart, 0.02 * kSpacing) << "body " << i;
        EXPECT_GT(turned, std::cos(0.5 * glm::radians(0.2)))
            << "body " << i << ": within 0.2 degrees";
        EXPECT_GT(gpu[i].contacts, 0u) << "body " << i << " rests on something";
        EXPECT_TRUE(finite(gpu[i]));
    }
    // The tilted box settled flat on the pedestal: its centre half a side above the top face.
    EXPECT_NEAR(gpu[3].position.y, 1.5 * kSide, 0.25 * kSpacing);
}

// A tilted box dropped onto the floor of an empty domain, with or without a second box resting
// in the far corner, out of its reach; the first body's state after `steps` and the dispatches
// of the last step.
struct DroppedBox {
    BodyState body;
    std::uint64_t dispatches = 0;
};

DroppedBox dropBox(bool withSecond, int steps) {
    format::Scene scene = testscene::emptyScene(kSpacing, 4, 16);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(0.6f, 0.5f, 0.4f);
    format::SceneCollider dropped = cubeBody(glm::vec3(0.15f, 0.25f, 0.2f), 0.8f);
    dropped.rotationDegrees = glm::vec3(10.0f, 0.0f, 25.0f);
    scene.colliders.push_back(dropped);
    if (withSecond)
        scene.colliders.push_back(cubeBody(glm::vec3(0.5f, 0.5f * kSide, 0.3f), 0.8f));
    std::vector<format::ColliderAsset> assets(scene.colliders.size(), cubeAsset(kSide));
    auto sim = Simulation::create(scene, std::move(assets));
    EXPECT_TRUE(sim) << sim.error().message();
    if (!sim)
        return {};
    GpuCommandCount before;
    for (int step = 0; step < steps; ++step) {
        before = sim->commandCount();
        sim->step();
    }
    return {sim->bodies()[0], (sim->commandCount() - before).dispatches};
}

TEST_F(SimulationBodies, ALoneBodyMovesTheSameInOneDispatchAsInFive) {
    // One body has no poses to exchange: its start and its four contact sweeps run in one
    // dispatch. With a second body the pass is five dispatches a substep, the poses passing
    // through the buffer between them. A second body out of reach changes nothing for the
    // first: the same arithmetic, so the same bits, while it falls, hits the floor on a corner,
    // rocks and settles.
    const DroppedBox alone = dropBox(false, 45);
    const DroppedBox paired = dropBox(true, 45);
    std::printf("dropped box: centre (%.5f, %.5f, %.5f) m, %u contacts; dispatches a step %llu "
                "alone, %llu with a second body\n",
                alone.body.position.x, alone.body.position.y, alone.body.position.z,
                alone.body.contacts, static_cast<unsigned long long>(alone.dispatches),
                static_cast<unsigned long long>(paired.dispatches));
    EXPECT_EQ(paired.dispatches, alone.dispatches + 4u * 4u) << "4 substeps, 4 more each";
    EXPECT_EQ(std::memcmp(&alone.body.position, &paired.body.position, sizeof(glm::vec3)), 0);
    EXPECT_EQ(std::memcmp(&alone.body.orientation, &paired.body.orientation, sizeof(glm::quat)), 0);
    EXPECT_EQ(
        std::memcmp(&alone.body.linearVelocity, &paired.body.linearVelocity, sizeof(glm::vec3)), 0);
    EXPECT_EQ(alone.body.contacts, paired.body.contacts);
    // It has landed: resting on the floor, settled flat on a face (half a side up).
    EXPECT_GT(alone.body.contacts, 0u);
    EXPECT_NEAR(alone.body.position.y, 0.5 * kSide, 0.25 * kSpacing);
    EXPECT_TRUE(finite(alone.body));
}

TEST_F(SimulationBodies, ABodyPassOfAnotherSizeIsRefused) {
    format::Scene scene = testscene::emptyScene(kSpacing, 8, 16);
    scene.colliders.push_back(cubeBody(glm::vec3(0.0f, 0.5f, 0.0f), 0.8f));
    for (std::uint32_t size : {1u, 4u, 100u, 1024u}) {
        SimulationOptions options;
        options.bodyGroupSize = size;
        auto sim = Simulation::create(scene, {cubeAsset(kSide)}, options);
        ASSERT_FALSE(sim) << size;
        EXPECT_NE(sim.error().message().find("invocations"), std::string::npos)
            << sim.error().message();
    }
}

TEST_F(SimulationBodies, ParticlesStartingInsideABodyAreLeftOutAndCounted) {
    format::Scene scene = tankScene(kTank, kDepth, 0.5f);
    // The cube's lower half is under water: rows 0.13 .. 0.27 in x and z (8 each), and the
    // layers with centres 0.13 .. 0.19 in y (4), lie inside it.
    scene.colliders.push_back(cubeBody(glm::vec3(0.2f, 0.2f, 0.2f), 0.5f));
    const std::size_t blocks = fillBlocks(scene).size();
    auto sim = Simulation::create(scene, {cubeAsset(kSide)});
    ASSERT_TRUE(sim) << sim.error().message();
    EXPECT_EQ(sim->particlesRemovedAtSpawn(), 8u * 8u * 4u);
    EXPECT_EQ(sim->particleCount(), blocks - 8 * 8 * 4);
    std::uint32_t maxId = 0;
    for (const ParticleState& p : sim->downloadParticles())
        maxId = std::max(maxId, p.id);
    EXPECT_EQ(maxId + 1, blocks) << "ids keep the blocks' numbering";
}

TEST_F(SimulationBodies, AnOpenMeshOrAFieldWithoutVolumeCannotBeABody) {
    format::Scene scene = tankScene(kTank, kDepth, 0.5f);
    scene.colliders.push_back(cubeBody(glm::vec3(0.2f, 0.3f, 0.2f), 0.5f));
    format::ColliderAsset open = cubeAsset(kSide);
    open.meta.mesh.triangles = 10;
    open.meta.mesh.boundaryEdges = 4;
    open.meta.mesh.closed = false;
    auto sim = Simulation::create(scene, {open});
    ASSERT_FALSE(sim);
    EXPECT_EQ(sim.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(sim.error().detail.find("tank.json: colliders[0].dynamic"), std::string::npos)
        << sim.error().detail;
    EXPECT_NE(sim.error().detail.find("open mesh"), std::string::npos) << sim.error().detail;

    // A field that is positive everywhere encloses nothing.
    format::ColliderAsset empty = testscene::assetOverBox(
        glm::dvec3(-0.1), glm::dvec3(0.1), 0.01, 0.0, [](const glm::dvec3&) { return 0.05; });
    auto none = Simulation::create(scene, {empty});
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(none.error().detail.find("colliders[0].dynamic"), std::string::npos);
    EXPECT_NE(none.error().detail.find("no volume"), std::string::npos) << none.error().detail;
}

TEST_F(SimulationBodies, DeterministicRunsWithBodiesGiveIdenticalBytes) {
    auto run = [](std::vector<ParticleState>& particles, std::vector<BodyState>& bodies) {
        format::Scene scene = tankScene(glm::vec2(0.3f, 0.3f), 0.12f, 0.4f);
        scene.colliders.push_back(cubeBody(glm::vec3(0.12f, 0.2f, 0.15f), 0.5f));
        scene.colliders.push_back(cubeBody(glm::vec3(0.2f, 0.3f, 0.16f), 1.5f));
        SimulationOptions options;
        options.deterministic = true;
        auto sim = Simulation::create(scene, {cubeAsset(0.1f), cubeAsset(0.08f)}, options);
        ASSERT_TRUE(sim) << sim.error().message();
        for (int step = 0; step < 30; ++step)
            sim->step();
        particles = sim->downloadParticles();
        bodies = sim->bodies();
    };
    std::vector<ParticleState> p1, p2;
    std::vector<BodyState> b1, b2;
    run(p1, b1);
    run(p2, b2);
    ASSERT_EQ(p1.size(), p2.size());
    ASSERT_EQ(b1.size(), 2u);
    ASSERT_EQ(b2.size(), 2u);
    EXPECT_EQ(0, std::memcmp(p1.data(), p2.data(), p1.size() * sizeof(ParticleState)));
    for (std::size_t b = 0; b < b1.size(); ++b) {
        EXPECT_EQ(0, std::memcmp(&b1[b].position, &b2[b].position, sizeof(glm::vec3)));
        EXPECT_EQ(0, std::memcmp(&b1[b].orientation, &b2[b].orientation, sizeof(glm::quat)));
        EXPECT_EQ(0, std::memcmp(&b1[b].linearVelocity, &b2[b].linearVelocity, sizeof(glm::vec3)));
        EXPECT_EQ(0, std::memcmp(&b1[b].force, &b2[b].force, sizeof(glm::vec3)));
        EXPECT_GT(glm::length(b1[b].position - glm::vec3(0.0f)), 0.0f);
    }
}

} // namespace
} // namespace sluice::rt
