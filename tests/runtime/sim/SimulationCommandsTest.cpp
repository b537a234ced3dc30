// The GPU commands a substep queues (docs/performance.md, "Dispatches and barriers"): counted
// where they are issued, pinned here pass by pass, and the prefix scan of the neighbour grid's
// sort, which also clears the counts it reads.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "grid/PrefixScan.h"
#include "shared/Pbf.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;
namespace fs = std::filesystem;

class SimulationCommands : public GpuTest {};

/// A 12 x 10 x 6 column in a tank: 720 particles, a dense grid of 24 x 20 x 6 cells.
format::Scene column(std::uint32_t substeps) {
    format::Scene scene = testscene::smallScene({12, 10, 6}, 0.02f, substeps);
    scene.simulation.minIterations = 2;
    scene.simulation.maxIterations = 8;
    return scene;
}

struct Counted {
    GpuCommandCount perStep; ///< queued by the last of the steps run
    StepStats stats;         ///< of the last step
};

Counted run(const format::Scene& scene, const SimulationOptions& options, int steps) {
    auto sim = Simulation::create(scene, {}, options);
    EXPECT_TRUE(sim) << sim.error().message();
    if (!sim)
        return {};
    GpuCommandCount before;
    for (int i = 0; i < steps; ++i) {
        before = sim->commandCount();
        sim->step();
    }
    return {sim->commandCount() - before, sim->readStats()};
}

// Without bodies, per substep: predict, the scan (180 cells: one block), the scatter-reorder,
// lambda and delta for each of the 8 iterations (issued whether or not the early stop leaves
// them idle; the delta that ends the solve also writes the velocities), vorticity and
// confinement, each followed by one barrier; per step, the statistics pass and its two
// barriers. The substep starts with no barrier of its own.
TEST_F(SimulationCommands, ASubstepIssuesItsPassesAndOneBarrierEach) {
    const std::uint32_t substeps = 3;
    const Counted counted = run(column(substeps), {}, 2);
    const std::uint64_t perSubstep = 1 + 1 + 1 + 2 * 8 + 2;
    EXPECT_EQ(counted.perStep.dispatches, substeps * perSubstep + 1);
    EXPECT_EQ(counted.perStep.indirect, substeps * 2 * 8u);
    EXPECT_EQ(counted.perStep.barriers, substeps * perSubstep + 2);
}

// The shipped early stop at 2 iterations: lambda and delta of iterations 0, 1 and 2 run (the
// third pair measures the error, stops and writes the velocities), the 10 after launch
// nothing: 11 dispatches run a substep with a one-block scan.
TEST_F(SimulationCommands, TheEarlyStopLeavesTheLaterIterationsIdle) {
    format::Scene scene = column(2);
    scene.simulation.targetDensityError = 1.0f; // the largest target: met at the first check
    const Counted counted = run(scene, {}, 2);
    ASSERT_EQ(counted.stats.iterations, 2u);
    EXPECT_EQ(counted.stats.solveDispatches, 2u * 6u);
    const std::uint64_t launched =
        counted.perStep.dispatches - (counted.perStep.indirect - counted.stats.solveDispatches);
    EXPECT_EQ(launched, 2u * 11u + 1u); // 11 a substep, and the statistics pass
    // And with no target every iteration runs.
    scene.simulation.targetDensityError = 0.0f;
    EXPECT_EQ(run(scene, {}, 2).stats.solveDispatches, 2u * 16u);
}

// --deterministic lists the slots, sorts each bucket and then gathers: two dispatches and two
// barriers more a substep than the scatter-reorder.
TEST_F(SimulationCommands, DeterministicRunsAddTheBucketSort) {
    SimulationOptions options;
    options.deterministic = true;
    const Counted fast = run(column(2), {}, 1);
    const Counted fixed = run(column(2), options, 1);
    EXPECT_EQ(fixed.perStep.dispatches, fast.perStep.dispatches + 2 * 2);
    EXPECT_EQ(fixed.perStep.barriers, fast.perStep.barriers + 2 * 2);
}

// Without vorticity confinement the omega pass is skipped.
TEST_F(SimulationCommands, NoVorticityDropsItsPass) {
    format::Scene scene = column(2);
    const Counted with = run(scene, {}, 1);
    scene.simulation.vorticity = 0.0f;
    const Counted without = run(scene, {}, 1);
    EXPECT_EQ(with.perStep.dispatches - without.perStep.dispatches, 2u);
    EXPECT_EQ(with.perStep.barriers - without.perStep.barriers, 2u);
}

// A grid of more cells than one block takes two scan dispatches: the blocks, then each block's
// offset added, summed from the totals before it by the add pass itself.
TEST_F(SimulationCommands, ALargeGridScansInBlocks) {
    const format::Scene small = column(1);
    format::Scene large = column(1);
    large.domainMax = glm::vec3(4.0f, 0.4f, 4.0f); // 100 x 10 x 100 cells of 4 cm
    large.simulation.capacity = 1u << 16;          // a hash table of as many buckets
    {
        auto sim = Simulation::create(large, {});
        ASSERT_TRUE(sim) << sim.error().message();
        ASSERT_EQ(sim->neighbourGridCells(), glm::uvec3(100, 10, 100));
    }
    ASSERT_GT(100u * 10u * 100u, shared::kScanBlock);
    const Counted one = run(small, {}, 1);
    const Counted blocks = run(large, {}, 1);
    EXPECT_EQ(blocks.perStep.dispatches, one.perStep.dispatches + 1);
    EXPECT_EQ(blocks.perStep.barriers, one.perStep.barriers + 1);
}

// The issue-27 budget: the shipped wave-with-sphere scene (a grid of 8,000-odd cells, 6
// substeps of the 8 iterations the early stop ends at 2) launches at most 12 dispatches a
// substep without bodies: predict, the scan's 2, the scatter-reorder, lambda and delta of
// iterations 0 to 2 (the last pair stops and writes the velocities), vorticity, confinement.
// Issued, the 10 idle iterations' dispatches count too.
TEST_F(SimulationCommands, TheWaveSphereSceneLaunchesTwelveDispatchesASubstep) {
    auto scene = format::readScene(fs::path(SLUICE_BUILD_ASSETS_DIR) / "wave-sphere.json");
    ASSERT_TRUE(scene) << scene.error().message();
    auto colliders = loadSceneColliders(*scene);
    ASSERT_TRUE(colliders) << colliders.error().message();
    auto sim = Simulation::create(*scene, *colliders);
    ASSERT_TRUE(sim) << sim.error().message();
    const glm::uvec3 cells = sim->neighbourGridCells();
    ASSERT_GT(cells.x * cells.y * cells.z, shared::kScanBlock) << "a scan of several blocks";
    const std::uint32_t substeps = scene->simulation.substeps;
    ASSERT_EQ(scene->simulation.maxIterations, 8u);
    sim->step();
    const GpuCommandCount before = sim->commandCount();
    sim->step();
    const GpuCommandCount perStep = sim->commandCount() - before;
    const StepStats stats = sim->readStats();
    ASSERT_EQ(stats.iterations, 2u) << "the early stop at its minimum, as shipped";
    const std::uint64_t launched = perStep.dispatches - (perStep.indirect - stats.solveDispatches);
    EXPECT_EQ(launched, substeps * 12u + 1u); // and the statistics pass
    EXPECT_EQ(perStep.dispatches, substeps * (12u + 10u) + 1u);
    EXPECT_EQ(perStep.barriers, perStep.dispatches + 1u);
}

// Neighbour lanes: the same dispatches, each neighbour pass launching `lanes` invocations per
// particle; the lanes record one mask and run the same early stop. A lane count that is not a
// power of two up to 32 is refused. A software renderer picks one lane.
TEST_F(SimulationCommands, NeighbourLanesWidenTheNeighbourPassesOnly) {
    format::Scene scene = column(2);
    scene.simulation.targetDensityError = 1.0f;
    const Counted one = run(scene, {}, 2);
    SimulationOptions options;
    options.neighbourLanes = 8;
    auto sim = Simulation::create(scene, {}, options);
    ASSERT_TRUE(sim) << sim.error().message();
    EXPECT_EQ(sim->neighbourLanes(), 8u);
    const GpuCommandCount before = sim->commandCount();
    sim->step();
    const GpuCommandCount perStep = sim->commandCount() - before;
    EXPECT_EQ(perStep.dispatches, one.perStep.dispatches);
    EXPECT_EQ(perStep.barriers, one.perStep.barriers);
    const std::uint32_t groups =
        (sim->particleCount() * 8 + shared::kPbfLocalSize - 1) / shared::kPbfLocalSize;
    const std::vector<std::uint32_t> launched = sim->solveGroups();
    ASSERT_EQ(launched.size(), 8u);
    EXPECT_EQ(launched[0], groups);
    EXPECT_EQ(launched[2], groups);
    EXPECT_EQ(launched[3], 0u) << "stopped at iteration 2, as with one lane";
    EXPECT_EQ(sim->readStats().iterations, 2u);

    auto automatic = Simulation::create(scene, {});
    ASSERT_TRUE(automatic);
    EXPECT_EQ(automatic->neighbourLanes(), 1u) << "llvmpipe: one invocation per particle";
    for (const std::uint32_t bad : {3u, 64u}) {
        options.neighbourLanes = bad;
        auto refused = Simulation::create(scene, {}, options);
        ASSERT_FALSE(refused);
        EXPECT_NE(refused.error().message().find("neighbour lanes"), std::string::npos);
    }
}

class PrefixScanTest : public GpuTest {};

// Both layouts against the CPU's sum, at the sizes where they meet: a shorter input read as
// zeros, and the input zeroed as it is read (the neighbour grid's counts).
TEST_F(PrefixScanTest, MatchesTheCpuAndClearsItsInput) {
    const std::uint32_t block = shared::kScanBlock;
    auto scan = PrefixScan::create(block * block + 5);
    ASSERT_TRUE(scan) << scan.error().message();
    std::mt19937 random(7);
    for (const std::uint32_t count :
         {1u, 2u, 1000u, block, block + 1, 65536u, block * block, block * block + 5}) {
        SCOPED_TRACE("count " + std::to_string(count));
        std::vector<std::uint32_t> input(count);
        for (std::uint32_t& v : input)
            v = random() % 9;
        auto in = gpu::Buffer::createFrom(input, "scan input");
        auto out = gpu::Buffer::create(std::size_t(count) * 4, "scan output");
        ASSERT_TRUE(in && out);
        // The last two inputs are left out: read as 0 and not cleared.
        const std::uint32_t used = count > 2 ? count - 2 : 0;
        const GpuCommandCount queued = scan->exclusive(*in, *out, ScanInput{count, used, true});
        EXPECT_EQ(queued.dispatches, count <= block ? 1u : 2u);
        EXPECT_EQ(queued.barriers, queued.dispatches);
        std::vector<std::uint32_t> want(count, 0), cleared = input;
        for (std::uint32_t i = 1; i < count; ++i)
            want[i] = want[i - 1] + (i - 1 < used ? input[i - 1] : 0u);
        std::fill(cleared.begin(), cleared.begin() + used, 0u);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        EXPECT_EQ(out->download<std::uint32_t>(), want);
        EXPECT_EQ(in->download<std::uint32_t>(), cleared);
        // In place, every input read.
        in->upload(input);
        scan->exclusive(*in, *in, count);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<std::uint32_t> all(count, 0);
        std::exclusive_scan(input.begin(), input.end(), all.begin(), 0u);
        EXPECT_EQ(in->download<std::uint32_t>(), all);
    }
}

// Past `reducedBlocks` blocks the totals are scanned by a level of their own (recursively):
// lowered to 4 here so that inputs of a few thousand elements take that path.
TEST_F(PrefixScanTest, ScansTheTotalsFirstPastTheBlocksItReduces) {
    const std::uint32_t block = shared::kScanBlock;
    const std::uint32_t reduced = 4;
    auto scan = PrefixScan::create(block * block + 5, reduced);
    ASSERT_TRUE(scan) << scan.error().message();
    // Dispatches: the blocks, then the totals' own scan when there are too many, then the add.
    const auto expected = [&](auto self, std::uint32_t count) -> std::uint32_t {
        const std::uint32_t blocks = (count + block - 1) / block;
        return count <= block ? 1u : 2u + (blocks <= reduced ? 0u : self(self, blocks));
    };
    std::mt19937 random(11);
    for (const std::uint32_t count :
         {block * reduced, block * reduced + 1, 65536u, block * block, block * block + 5}) {
        SCOPED_TRACE("count " + std::to_string(count));
        std::vector<std::uint32_t> input(count);
        for (std::uint32_t& v : input)
            v = random() % 9;
        auto in = gpu::Buffer::createFrom(input, "scan input");
        ASSERT_TRUE(in);
        const GpuCommandCount queued = scan->exclusive(*in, *in, count);
        EXPECT_EQ(queued.dispatches, expected(expected, count));
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<std::uint32_t> want(count, 0);
        std::exclusive_scan(input.begin(), input.end(), want.begin(), 0u);
        EXPECT_EQ(in->download<std::uint32_t>(), want);
    }
    EXPECT_EQ(expected(expected, block * reduced + 1), 3u) << "the totals scanned in one block";
    EXPECT_EQ(expected(expected, block * block + 5), 4u) << "and reduced a level up";
}

} // namespace
} // namespace sluice::rt
