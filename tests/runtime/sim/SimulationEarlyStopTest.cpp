// The early stop of the solve (docs/pbf.md step 4): the iterations after it launch no work and
// change nothing, whichever ping-pong buffer the last update landed in.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "ReferencePbf.h"
#include "RuntimeTestScenes.h"
#include "shared/Pbf.h"
#include "sim/ParticleCompare.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using test::maxPositionDifference;

using gpu::test::GpuTest;

class SimulationEarlyStop : public GpuTest {};

// A 10 x 20 x 3 column released in a tank three times its width: it collapses and splashes,
// so every iteration moves the particles and a wrong buffer shows in the bytes.
format::Scene collapsingColumn(std::uint32_t minIterations, std::uint32_t maxIterations,
                               float targetDensityError) {
    format::Scene scene = testscene::smallScene({10, 20, 3}, 0.02f, 3);
    scene.domainMax->x *= 3.0f;
    scene.simulation.minIterations = minIterations;
    scene.simulation.maxIterations = maxIterations;
    scene.simulation.targetDensityError = targetDensityError;
    return scene;
}

struct Played {
    std::vector<unsigned char> bytes;  ///< positions, velocities and ids after the last step
    std::vector<std::uint32_t> groups; ///< Simulation::solveGroups() after the last step
    std::uint32_t iterations = 0;
    std::uint32_t particles = 0;
};

Played play(const format::Scene& scene, int steps) {
    SimulationOptions options;
    options.deterministic = true;
    auto sim = Simulation::create(scene, {}, options);
    EXPECT_TRUE(sim) << sim.error().message();
    if (!sim)
        return {};
    for (int step = 0; step < steps; ++step)
        sim->step();
    Played run;
    const auto particles = sim->downloadParticles();
    run.bytes.resize(particles.size() * sizeof(ParticleState));
    std::memcpy(run.bytes.data(), particles.data(), run.bytes.size());
    run.groups = sim->solveGroups();
    run.iterations = sim->readStats().iterations;
    run.particles = sim->particleCount();
    return run;
}

// One step of `scene` on the GPU and on the CPU reference (which runs no idle iterations): the
// iterations of the last substep on each, and how far apart their particles end.
struct AgainstTheReference {
    std::uint32_t gpuIterations = 0;
    std::uint32_t cpuIterations = 0;
    double maxDifference = 0.0; ///< [m]
};

AgainstTheReference stepBoth(const format::Scene& scene) {
    ref::ReferencePbf cpu(scene, {});
    SimulationOptions options;
    options.deterministic = true;
    auto gpu = Simulation::create(scene, {}, options);
    EXPECT_TRUE(gpu) << gpu.error().message();
    if (!gpu)
        return {};
    gpu->step();
    cpu.step();
    return {gpu->readStats().iterations, cpu.stats().iterationsLastSubstep,
            maxPositionDifference(gpu->downloadParticles(), cpu.particles())};
}

// The stop comes after an even count only (docs/pbf.md step 4.2, "The early stop's parity"):
// a target every iteration meets, from minIterations K, stops at the first even count from K,
// on the GPU and on the CPU reference, which runs no idle iterations, with the same positions.
// A solve of 3 fixed iterations ends in the other pred buffer. This fails if the velocity pass
// reads the other pred buffer than the last update wrote.
TEST_F(SimulationEarlyStop, TheStopComesAfterAnEvenCountAndTheVelocityPassReadsTheLastUpdate) {
    for (std::uint32_t k : {1u, 2u, 3u}) {
        SCOPED_TRACE("K = " + std::to_string(k));
        format::Scene scene = collapsingColumn(k, 8, 1.0f);
        const AgainstTheReference run = stepBoth(scene);
        const std::uint32_t even = k + (k & 1u);
        EXPECT_EQ(run.gpuIterations, even);
        EXPECT_EQ(run.cpuIterations, even);
        EXPECT_LT(run.maxDifference, 1e-4 * scene.simulation.kernelRadius);
    }
    const format::Scene fixed = collapsingColumn(3, 3, 0.0f);
    const AgainstTheReference run = stepBoth(fixed);
    EXPECT_EQ(run.gpuIterations, 3u);
    EXPECT_LT(run.maxDifference, 1e-4 * fixed.simulation.kernelRadius);
}

// A target every iteration meets stops the solve at exactly minIterations = K (even) in every
// substep: K updates, then K + 1 .. 7 idle. That must be the bytes of K fixed iterations
// (no target, maxIterations K).
TEST_F(SimulationEarlyStop, StoppingAtIterationKGivesTheBytesOfKFixedIterations) {
    for (std::uint32_t k : {2u, 4u}) {
        SCOPED_TRACE("K = " + std::to_string(k));
        const Played stopped = play(collapsingColumn(k, 8, 1.0f), 8);
        const Played fixed = play(collapsingColumn(k, k, 0.0f), 8);
        ASSERT_GT(stopped.particles, 500u);
        EXPECT_EQ(stopped.iterations, k);
        EXPECT_EQ(fixed.iterations, k);
        ASSERT_EQ(stopped.bytes.size(), fixed.bytes.size());
        EXPECT_TRUE(stopped.bytes == fixed.bytes) << "the idle iterations changed the result";
    }
    // And the number of iterations matters, so the comparison above could fail.
    EXPECT_FALSE(play(collapsingColumn(2, 8, 1.0f), 8).bytes ==
                 play(collapsingColumn(4, 8, 1.0f), 8).bytes);
}

// Lambda and delta of iteration K run (lambda measures the error, delta decides the stop);
// every later iteration launches no work group.
TEST_F(SimulationEarlyStop, IterationsAfterTheStopLaunchNoWorkGroups) {
    const Played stopped = play(collapsingColumn(2, 8, 1.0f), 2);
    const std::uint32_t groups =
        (stopped.particles + shared::kPbfLocalSize - 1) / shared::kPbfLocalSize;
    ASSERT_GT(groups, 0u);
    const std::vector<std::uint32_t> expected = {groups, groups, groups, 0, 0, 0, 0, 0};
    EXPECT_EQ(stopped.groups, expected);

    const Played fixed = play(collapsingColumn(2, 8, 0.0f), 2); // no target: all 8 run
    EXPECT_EQ(fixed.groups, std::vector<std::uint32_t>(8, groups));
    EXPECT_EQ(fixed.iterations, 8u);
}

} // namespace
} // namespace sluice::rt
