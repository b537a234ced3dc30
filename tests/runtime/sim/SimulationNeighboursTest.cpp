// The per-substep neighbour mask (docs/pbf.md step 3): it records exactly N(i), on the dense
// grid and on the hash, counts the particles whose candidates outnumber its bits, and keeps
// the memory per particle within 256 bytes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "shared/Pbf.h"
#include "sim/NeighbourRecords.h"
#include "sluice/gpu/colliders/ColliderRecord.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;

class SimulationNeighbours : public GpuTest {};

// A column that has fallen for a few steps, so the particles are off the lattice.
format::Scene fallingColumn(bool denseGrid) {
    format::Scene scene = testscene::smallScene({8, 12, 5}, 0.02f, 2);
    scene.domainMax->x *= 2.0f;
    if (!denseGrid) {
        scene.domainMin.reset();
        scene.domainMax.reset();
    }
    return scene;
}

struct Check {
    std::size_t pairs = 0;      ///< recorded (i, j) pairs
    std::size_t borderline = 0; ///< pairs skipped because |d| is h to float rounding
    std::uint32_t maxCandidates = 0;
    std::uint32_t pastMaskParticles = 0;
};

// Compares every particle's recorded N(i) with a brute-force search over the start positions:
// every j with |x*_i - x*_j| < h recorded once, nothing else. Pairs within 1e-5 h^2 of h^2
// may fall either way (the GPU may fuse the distance's multiply-adds) and are not judged.
Check checkAgainstBruteForce(const Simulation& sim) {
    const auto records = test::recordedNeighbours(sim);
    const float h = sim.constants().h;
    const double h2 = double(h) * h;
    Check check;
    std::map<std::uint32_t, glm::vec3> startById;
    for (const auto& r : records)
        startById[r.id] = r.start;
    EXPECT_EQ(startById.size(), records.size()) << "ids are unique";
    for (const auto& r : records) {
        std::multiset<std::uint32_t> got(r.fromMask.begin(), r.fromMask.end());
        got.insert(r.pastMask.begin(), r.pastMask.end());
        check.pairs += got.size();
        check.maxCandidates = std::max(check.maxCandidates, r.candidates);
        if (r.candidates > shared::kNeighbourMaskBits)
            ++check.pastMaskParticles;
        for (const auto& [id, x] : startById) {
            if (id == r.id)
                continue;
            const glm::dvec3 d = glm::dvec3(r.start) - glm::dvec3(x);
            const double q2 = glm::dot(d, d);
            if (std::abs(q2 - h2) < 1e-5 * h2) {
                ++check.borderline;
                continue;
            }
            const std::size_t n = got.count(id);
            if (q2 < h2)
                EXPECT_EQ(n, 1u) << "particle " << r.id << " misses neighbour " << id << " at "
                                 << std::sqrt(q2) / h << " h";
            else
                EXPECT_EQ(n, 0u) << "particle " << r.id << " records " << id << " at "
                                 << std::sqrt(q2) / h << " h";
        }
    }
    return check;
}

TEST_F(SimulationNeighbours, TheMaskRecordsExactlyTheNeighboursWithinHOnBothGrids) {
    for (bool dense : {true, false}) {
        SCOPED_TRACE(dense ? "dense grid" : "hash");
        auto sim = Simulation::create(fallingColumn(dense), {});
        ASSERT_TRUE(sim) << sim.error().message();
        EXPECT_EQ(sim->neighbourGridCells().x > 0, dense);
        for (int step = 0; step < 6; ++step)
            sim->step();
        const StepStats stats = sim->readStats();
        const Check check = checkAgainstBruteForce(*sim);
        // A small block, many particles on its surface: 14 (falling freely) to 20 each.
        EXPECT_GT(check.pairs, 10u * sim->particleCount());
        EXPECT_EQ(check.pastMaskParticles, 0u);
        EXPECT_EQ(stats.maskOverflow, 0u);
        EXPECT_EQ(stats.maxCandidates >= check.maxCandidates, true);
        EXPECT_GT(stats.maxNeighbours, 15u);
    }
}

// h = 4 s on a lattice: about 1,700 candidates per interior particle, far past the mask's
// bits. The overflow is counted (once per particle and substep) and the candidates past the
// mask are still tested, so N(i) stays exact.
TEST_F(SimulationNeighbours, CandidatesPastTheMaskAreCountedAndStillFound) {
    format::Scene scene = testscene::smallScene({12, 12, 12}, 0.02f, 1);
    scene.simulation.kernelRadius = 4.0f * scene.simulation.spacing;
    scene.simulation.timeStep = 1.0f / 600.0f;
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    sim->step();
    const StepStats stats = sim->readStats();
    const Check check = checkAgainstBruteForce(*sim);
    EXPECT_GT(check.pastMaskParticles, 100u);
    EXPECT_EQ(stats.maskOverflow, check.pastMaskParticles) << "one substep: one count each";
    EXPECT_GT(stats.maxCandidates, shared::kNeighbourMaskBits);
    EXPECT_EQ(stats.maxCandidates, check.maxCandidates);
    EXPECT_EQ(stats.nonFinite, 0u);
}

// Memory per particle of capacity, colliders aside, mask included: 132 bytes of particle
// arrays, 48 of mask and 16 to 32 of hash table (2 to 4 buckets a particle; the worst just
// above a power of two, where the table doubles), so at most 212 bytes at every capacity and
// at most 200 where the table holds about two buckets a particle (a capacity just under a
// power of two, as the shipped 15k and 1M scenes have).
TEST_F(SimulationNeighbours, MemoryPerParticleStaysWithin212Bytes) {
    for (std::uint32_t capacity : {512u, 1000u, 1025u, 4097u, 30000u, 32769u}) {
        format::Scene scene = testscene::emptyScene(0.02f, 1, capacity);
        auto sim = Simulation::create(scene, {});
        ASSERT_TRUE(sim) << sim.error().message();
        EXPECT_LE(sim->bytesPerParticle(), 212u) << capacity;
        EXPECT_GE(sim->bytesPerParticle(), 148u + 4u * shared::kNeighbourMaskWords) << capacity;
        // Everything allocated, spread over the capacity: the particles' share and what every
        // scene has once (the parameters, the statistics, the colliders' uniform block).
        const double once = 4096.0 + double(gpu::kColliderRecordBytes);
        EXPECT_LE(double(sim->gpuBytes()) / capacity, 212.0 + once / capacity) << capacity;
    }
    for (std::uint32_t capacity : {1000u, 30000u}) {
        format::Scene scene = testscene::emptyScene(0.02f, 1, capacity);
        auto sim = Simulation::create(scene, {});
        ASSERT_TRUE(sim) << sim.error().message();
        EXPECT_LE(sim->bytesPerParticle(), 200u) << capacity;
    }
}

} // namespace
} // namespace sluice::rt
