// Removing particles (docs/embedding.md, "Removing particles"): drains remove exactly what enters
// them, spawned water drained leaves the count where it started, removal by id and by box, and
// bad input refused.
#include <cmath>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;

class SimulationRemoval : public GpuTest {};

bool inBox(glm::vec3 x, const format::Drain& box) {
    return glm::all(glm::greaterThanEqual(x, box.min)) && glm::all(glm::lessThan(x, box.max));
}

std::set<std::uint32_t> idsOf(const std::vector<ParticleState>& particles) {
    std::set<std::uint32_t> ids;
    for (const ParticleState& p : particles)
        ids.insert(p.id);
    return ids;
}

// A column collapsing into a tank whose right third is a drain: with one substep a step, the
// particles a step removes are exactly those whose position at its start lay in the drain.
TEST_F(SimulationRemoval, DrainsRemoveExactlyTheParticlesThatEnterThem) {
    format::Scene scene = testscene::smallScene({6, 8, 4}, 0.02f, 1);
    scene.domainMax->x = 0.36f;
    const format::Drain drain{{0.2f, 0.0f, 0.0f}, {0.36f, 0.32f, 0.08f}};
    scene.drains.push_back(drain);
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    std::vector<ParticleState> before = sim->downloadParticles();
    std::size_t removedInAll = 0;
    for (int step = 0; step < 40; ++step) {
        std::set<std::uint32_t> expected;
        for (const ParticleState& p : before)
            if (!inBox(p.position, drain))
                expected.insert(p.id);
        removedInAll += before.size() - expected.size();
        sim->step();
        const std::vector<ParticleState> after = sim->downloadParticles();
        ASSERT_EQ(idsOf(after), expected) << "step " << step;
        for (const ParticleState& p : after)
            ASSERT_TRUE(std::isfinite(p.position.x)) << "step " << step;
        EXPECT_EQ(sim->readStats().particles, after.size()) << "step " << step;
        before = after;
    }
    EXPECT_GT(removedInAll, 20u) << "the water reached the drain";
    // The slots of the removed particles are given back a step or two after the removals stop.
    ASSERT_TRUE(sim->setDrains({}));
    glFinish(); // the test waits so the live count's copy is done; a game never needs to
    for (int step = 0; step < 3; ++step)
        sim->step();
    EXPECT_EQ(sim->particleCount(), sim->readStats().particles);
    EXPECT_EQ(sim->particleCount(), sim->downloadParticles().size());
}

TEST_F(SimulationRemoval, SpawnedWaterRunningIntoADrainLeavesTheCountWhereItStarted) {
    // Weightless, so the pool stays where it is and the jet flies straight into the drain.
    format::Scene scene = testscene::smallScene({6, 2, 6}, 0.02f, 2);
    scene.simulation.gravity = glm::vec3(0.0f);
    scene.simulation.capacity += 200;
    scene.domainMax = glm::vec3(0.3f, 0.24f, 0.12f);
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    ASSERT_TRUE(sim->setDrains({{{0.22f, 0.0f, 0.0f}, {0.3f, 0.24f, 0.12f}}}));
    sim->step();
    const std::uint32_t start = sim->readStats().particles;
    ASSERT_EQ(start, 72u);
    std::vector<glm::vec3> jet;
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 5; ++k)
            jet.emplace_back(0.12f + 0.02f * float(i), 0.14f, 0.02f + 0.02f * float(k));
    auto first = sim->addParticles(jet, std::vector<glm::vec3>(jet.size(), {1.0f, 0.0f, 0.0f}));
    ASSERT_TRUE(first) << first.error().message();
    EXPECT_EQ(sim->readStats().particles, start) << "statistics of the last step";
    sim->step();
    EXPECT_EQ(sim->readStats().particles, start + 20) << "none has reached the drain yet";
    for (int i = 0; i < 10; ++i) // 1 m/s for 1/6 s: 17 cm, past the drain's edge at 22 cm
        sim->step();
    EXPECT_EQ(sim->readStats().particles, start);
    EXPECT_EQ(sim->liveParticleCount(), start);
    for (const ParticleState& p : sim->downloadParticles())
        EXPECT_LT(p.id, *first) << "a spawned particle is still there";
}

TEST_F(SimulationRemoval, RemovedByIdOrBoxTheOthersKeepTheirIds) {
    format::Scene scene = testscene::smallScene({6, 4, 6}, 0.02f, 2);
    SimulationOptions options;
    options.deterministic = true;
    auto sim = Simulation::create(scene, {}, options);
    ASSERT_TRUE(sim) << sim.error().message();
    sim->step();
    const std::set<std::uint32_t> all = idsOf(sim->downloadParticles());
    ASSERT_TRUE(sim->removeParticles({3, 7, 7, 100}));
    // The top layer: y from 0.06 to 0.08 at rest.
    ASSERT_TRUE(sim->removeParticlesIn({-1.0f, 0.065f, -1.0f}, {1.0f, 1.0f, 1.0f}));
    sim->step();
    std::set<std::uint32_t> expected = all;
    for (std::uint32_t id : {3u, 7u, 100u})
        expected.erase(id);
    const std::set<std::uint32_t> now = idsOf(sim->downloadParticles());
    for (std::uint32_t id : now)
        EXPECT_TRUE(expected.count(id)) << "id " << id << " should be gone";
    EXPECT_EQ(all.size() - now.size(), 3u + 36u) << "three by id, the top layer of 36 by the box";
    // One-shot: the box removes nothing more at the next step.
    sim->step();
    EXPECT_EQ(idsOf(sim->downloadParticles()).size(), now.size());
    // Removing an id twice is harmless.
    ASSERT_TRUE(sim->removeParticles({3}));
    sim->step();
    EXPECT_EQ(idsOf(sim->downloadParticles()).size(), now.size());
}

TEST_F(SimulationRemoval, RemovalRefusesBadInputAndChangesNothing) {
    format::Scene scene = testscene::smallScene({4, 4, 4});
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    auto out = sim->removeParticles({2, 64});
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(out.error().detail.find("id 64 was never given out"), std::string::npos);
    out = sim->removeParticlesIn({0.0f, 0.1f, 0.0f}, {1.0f, 0.05f, 1.0f});
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    out = sim->removeParticlesIn({0.0f, std::nanf(""), 0.0f}, {1.0f, 1.0f, 1.0f});
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::NonFinite);
    out = sim->setDrains(std::vector<format::Drain>(9, {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}}));
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    EXPECT_TRUE(sim->drains().empty());
    sim->step();
    EXPECT_EQ(sim->readStats().particles, 64u);
    EXPECT_EQ(sim->downloadParticles().size(), 64u);
}

} // namespace
} // namespace sluice::rt
