// The GPU solver against the CPU reference (tests/reference), particle by particle.
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "ReferencePbf.h"
#include "RuntimeTestScenes.h"
#include "sim/ParticleCompare.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using test::maxPositionDifference;
using test::meanPositionDifference;

using gpu::test::GpuTest;

// A 10 x 16 x 13 block (2080 particles) standing on a rotated, scaled floor collider, with a
// sphere collider moving into its side: gravity, the solver and both collision paths (with
// friction, and with a moving collider) all act. The block is not symmetric, so float rounding
// cannot tip particles off a symmetry plane one way on the GPU and the other on the CPU.
struct ParityScene {
    format::Scene scene;
    std::vector<format::ColliderAsset> assets;
};

ParityScene parityScene() {
    ParityScene p;
    const float s = 0.02f;
    p.scene = testscene::smallScene({10, 16, 13}, s, 2);
    // Walls around the block's footprint keep the flow gentle: a free column would collapse
    // and splash, and a splash is chaotic (rounding differences grow without bound).
    p.scene.domainMin = glm::vec3(-0.10f, -1.0f, -0.13f);
    p.scene.domainMax = glm::vec3(0.10f, 1.0f, 0.13f);
    p.scene.blocks[0].min = glm::vec3(-0.10f, 0.0f, -0.13f);
    p.scene.blocks[0].max = glm::vec3(0.10f, 0.32f, 0.13f);
    // Floor: its top at y = 0, one particle radius under the bottom layer.
    testscene::addTiltedFloor(p.scene, p.assets);
    // A ball of radius 0.1 m 5 mm above the water, moving down into it at 0.3 m/s.
    p.assets.push_back(testscene::sphereColliderAsset({0.0, 0.0, 0.0}, 0.1, 0.01));
    format::SceneCollider ball;
    ball.asset = "ball.slc";
    ball.translation = glm::vec3(0.0153f, 0.4251f, 0.0171f); // no particle on a cell face
    ball.linearVelocity = glm::vec3(0.0f, -0.3f, 0.0f);
    p.scene.colliders.push_back(ball);
    return p;
}

// Both neighbour grids: the domain box as above gives 5 x 50 x 7 cells, fewer than the hash
// table's 8192 buckets, so the solver uses the dense grid; the same box reaching up to y = 100 m
// (nothing gets there) needs 5 x 2525 x 7 cells and the solver hashes instead.
// Each grid also with the neighbour passes split over lanes (4 and 8 invocations per particle,
// the layouts a GPU picks for small scenes): the same sums in another fixed order. The walls
// and both colliders add boundary volume (docs/pbf.md, "Boundary volume").
struct ParityCase {
    bool dense;
    std::uint32_t lanes;
};

void PrintTo(const ParityCase& c, std::ostream* os) {
    *os << (c.dense ? "dense grid, " : "hash, ") << c.lanes << " lanes";
}

class SimulationParity : public GpuTest, public ::testing::WithParamInterface<ParityCase> {};

INSTANTIATE_TEST_SUITE_P(Grids, SimulationParity,
                         ::testing::Values(ParityCase{true, 1}, ParityCase{false, 1},
                                           ParityCase{true, 4}, ParityCase{false, 8}),
                         [](const auto& param) {
                             return std::string(param.param.dense ? "Dense" : "Hash") +
                                    (param.param.lanes > 1
                                         ? std::to_string(param.param.lanes) + "Lanes"
                                         : "");
                         });

TEST_P(SimulationParity, AgreesWithTheCpuReferenceAfterOneStepAndStaysCloseAfterTwenty) {
    ParityScene p = parityScene();
    const bool dense = GetParam().dense;
    if (!dense)
        p.scene.domainMax->y = 100.0f;
    std::vector<ref::ReferenceCollider> refColliders;
    for (std::size_t c = 0; c < p.assets.size(); ++c)
        refColliders.push_back({&p.assets[c], p.scene.colliders[c]});
    ref::ReferencePbf cpu(p.scene, refColliders);
    SimulationOptions options;
    options.deterministic = true;
    options.neighbourLanes = GetParam().lanes;
    auto gpu = Simulation::create(p.scene, p.assets, options);
    ASSERT_TRUE(gpu) << gpu.error().message();
    ASSERT_EQ(gpu->neighbourLanes(), GetParam().lanes);
    ASSERT_EQ(gpu->particleCount(), cpu.particles().size());
    ASSERT_GT(gpu->particleCount(), 1900u);
    const double h = p.scene.simulation.kernelRadius;
    if (dense)
        EXPECT_EQ(gpu->neighbourGridCells(), glm::uvec3(5, 50, 7));
    else
        EXPECT_EQ(gpu->neighbourGridCells(), glm::uvec3(0));

    // Before stepping: the same particles.
    EXPECT_EQ(maxPositionDifference(gpu->downloadParticles(), cpu.particles()), 0.0);

    gpu->step();
    cpu.step();
    const double afterOne = maxPositionDifference(gpu->downloadParticles(), cpu.particles());
    EXPECT_LT(afterOne, 1e-4 * h) << "after one step, in units of h: " << afterOne / h;
    const StepStats stats = gpu->readStats();
    EXPECT_NEAR(stats.avgDensityError, cpu.stats().avgDensityError, 1e-4);
    EXPECT_NEAR(stats.maxDensityError, cpu.stats().maxDensityError, 1e-3);
    EXPECT_EQ(stats.iterations, cpu.stats().iterationsLastSubstep);

    // PBF amplifies rounding: the flow is chaotic, so after 20 steps GPU and CPU differ by the
    // amount the CPU reference differs from itself when every particle is nudged by 1e-7 m
    // (rounding size). Staying close means staying within a small factor of that envelope.
    ref::ReferencePbf nudged(p.scene, refColliders);
    for (ParticleState& q : nudged.mutableParticles())
        q.position.x += 1e-7f * float(int(q.id % 3) - 1);
    nudged.step();
    for (int i = 1; i < 20; ++i) {
        gpu->step();
        cpu.step();
        nudged.step();
    }
    const auto gpuState = gpu->downloadParticles();
    const double afterTwenty = maxPositionDifference(gpuState, cpu.particles());
    const double envelope = maxPositionDifference(nudged.particles(), cpu.particles());
    EXPECT_LT(afterTwenty, 3.0 * envelope + 1e-3 * h)
        << "after 20 steps, in units of h: GPU-CPU " << afterTwenty / h << ", CPU-nudged CPU "
        << envelope / h;
    EXPECT_LT(meanPositionDifference(gpuState, cpu.particles()),
              3.0 * meanPositionDifference(nudged.particles(), cpu.particles()) + 1e-4 * h);
    const StepStats late = gpu->readStats();
    EXPECT_EQ(late.insideColliders, cpu.stats().insideColliders);
    EXPECT_EQ(late.nonFinite, 0u);
    EXPECT_NEAR(late.avgDensityError, cpu.stats().avgDensityError,
                0.1 * cpu.stats().avgDensityError + 1e-4);
    EXPECT_NEAR(late.maxSpeed, cpu.stats().maxSpeed, 0.5 * cpu.stats().maxSpeed);
}

// The neighbour passes fetch other particles' positions, velocities, masks and cell ranges
// through texel views, or read them from the storage blocks where a buffer is past the GL's
// texel-buffer limit: the same bits, on both grids and over lanes.
// Five steps of the parity scene (vorticity and XSPH on, the ball moving in): a view that read
// the wrong buffer, or nothing (an unbound unit reads zeros), would move particles in the first.
TEST_P(SimulationParity, TheStorageReadsGiveTheTexelViewsBits) {
    std::vector<ParticleState> runs[2];
    for (int fromStorage = 0; fromStorage < 2; ++fromStorage) {
        ParityScene p = parityScene();
        if (!GetParam().dense)
            p.scene.domainMax->y = 100.0f;
        SimulationOptions options;
        options.deterministic = true;
        options.neighbourLanes = GetParam().lanes;
        options.neighboursFromStorage = fromStorage != 0;
        auto sim = Simulation::create(p.scene, p.assets, options);
        ASSERT_TRUE(sim) << sim.error().message();
        EXPECT_EQ(sim->neighbourTexels(), fromStorage == 0);
        for (int step = 0; step < 5; ++step)
            sim->step();
        runs[fromStorage] = sim->downloadParticles();
    }
    ASSERT_GT(runs[0].size(), 1900u);
    EXPECT_EQ(test::differingParticles(runs[0], runs[1]), 0u);
}

} // namespace
} // namespace sluice::rt
