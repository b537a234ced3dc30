// Dynamic bodies in the GPU solver (docs/bodies.md): Archimedes' draft, sinking and rising,
// momentum exchange, contacts, robustness and determinism, on llvmpipe-sized scenes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "sluice/rt/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;

class SimulationBodies : public GpuTest {};

constexpr float kSpacing = 0.02f;

// A tank of `tank` (x, z) [m] holding water `depth` deep, open above up to `height`.
format::Scene tankScene(glm::vec2 tank, float depth, float height, std::uint32_t substeps = 4) {
    format::Scene scene;
    scene.path = "tank.json";
    scene.name = "tank";
    const glm::uvec3 counts(std::uint32_t(std::lround(tank.x / kSpacing)),
                            std::uint32_t(std::lround(depth / kSpacing)),
                            std::uint32_t(std::lround(tank.y / kSpacing)));
    scene.simulation =
        testscene::defaultParams(kSpacing, substeps, counts.x * counts.y * counts.z);
    scene.simulation.targetDensityError = 0.005f;
    format::FluidBlock block;
    block.min = glm::vec3(0.0f);
    block.max = glm::vec3(counts) * kSpacing;
    scene.blocks.push_back(block);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(tank.x, height, tank.y);
    return scene;
}

// A dynamic collider centred at `centre`, `ratio` times the water's density.
format::SceneCollider cubeBody(glm::vec3 centre, float ratio) {
    format::SceneCollider c;
    c.asset = "cube.slc";
    c.translation = centre;
    format::DynamicBody d;
    d.density = ratio * 1000.0f;
    c.dynamic = d;
    return c;
}

format::ColliderAsset cubeAsset(float side) {
    const double h = 0.5 * side;
    return testscene::boxColliderAsset(glm::dvec3(-h), glm::dvec3(h), 0.25 * kSpacing);
}

// Height of the water surface away from the body, by mass: hydrostatic pressure at height y
// is the weight of the water above it, so the surface Archimedes' law refers to is
// y + (volume m / rho0 of the particles above y) / (their floor area). Measured above `below`
// (the body's lowest point), over the columns farther than `clear` [m] horizontally from
// `centre` and two spacings from the walls (the wall layers sit closer than the rest spacing).
// The top particles' heights are not that surface: PBF's surface layer sits closer than the
// rest spacing too.
double waterLevel(const std::vector<ParticleState>& particles, glm::vec3 centre, double clear,
                  glm::vec2 tank, double particleVolume, double below) {
    const double margin = 2.0 * kSpacing;
    std::uint64_t above = 0;
    for (const ParticleState& p : particles) {
        const glm::vec2 d(p.position.x - centre.x, p.position.z - centre.z);
        if (std::max(std::abs(d.x), std::abs(d.y)) < clear || p.position.x < margin ||
            p.position.z < margin || p.position.x > tank.x - margin ||
            p.position.z > tank.y - margin || p.position.y < below)
            continue;
        ++above;
    }
    const double area =
        (double(tank.x) - 2.0 * margin) * (double(tank.y) - 2.0 * margin) - 4.0 * clear * clear;
    return below + double(above) * particleVolume / area;
}

// Lowest point of the cube of side `side` at the body's pose.
double lowestPoint(const BodyState& body, float side) {
    double lowest = 1e30;
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner = (glm::vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1) - 0.5f) * side;
        lowest = std::min(lowest, double(body.pose.toWorld(corner).y));
    }
    return lowest;
}

// Share of the cube's volume below height `level`: 24^3 points inside it at its pose.
double submergedShare(const BodyState& body, float side, double level) {
    const int n = 24;
    int below = 0;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const glm::vec3 local =
                    (glm::vec3(i, j, k) + 0.5f) / float(n) * side - glm::vec3(0.5f * side);
                if (body.pose.toWorld(local).y < level)
                    ++below;
            }
    return double(below) / double(n * n * n);
}

struct Settled {
    double share = 0.0;       ///< submerged share at the end
    double verticalRms = 0.0; ///< rms vertical speed of the body over the last second [m/s]
    BodyState body;
    StepStats stats;
    std::uint32_t worstInside = 0;
    std::uint32_t worstNonFinite = 0;
};

Settled floatCube(float ratio, float side, float startShare, int seconds) {
    const glm::vec2 tank(0.4f, 0.4f);
    const float depth = 0.2f;
    format::Scene scene = tankScene(tank, depth, 0.5f);
    const float y = depth + side * (0.5f - startShare);
    scene.colliders.push_back(cubeBody(glm::vec3(0.2f, y, 0.2f), ratio));
    std::vector<format::ColliderAsset> assets{cubeAsset(side)};
    auto sim = Simulation::create(scene, std::move(assets));
    EXPECT_TRUE(sim) << sim.error().message();
    if (!sim)
        return {};
    Settled out;
    const int steps = 60 * seconds;
    double squares = 0.0;
    int counted = 0;
    for (int step = 1; step <= steps; ++step) {
        sim->step();
        const StepStats stats = sim->readStats();
        out.worstInside = std::max(out.worstInside, stats.insideColliders);
        out.worstNonFinite = std::max(out.worstNonFinite, stats.nonFinite);
        const BodyState body = sim->bodies().at(0);
        if (step > steps - 60) {
            squares += double(body.linearVelocity.y) * body.linearVelocity.y;
            ++counted;
        }
        if (step % 30 == 0) {
            const double level = waterLevel(sim->downloadParticles(), body.position, 0.6 * side, tank,
                                           sim->constants().volume, lowestPoint(body, side));
            std::printf("ratio %.2f t %.2f s: level %.4f y %.4f v %.4f share %.3f force %.3f N (weight %.3f "
                        "N) contacts %u\n",
                        ratio, step / 60.0, level, body.position.y, body.linearVelocity.y,
                        submergedShare(body, side, level), body.force.y, body.mass * 9.81,
                        body.contacts);
        }
    }
    out.body = sim->bodies().at(0);
    out.stats = sim->readStats();
    const double level = waterLevel(sim->downloadParticles(), out.body.position, 0.6 * side,
                                    tank, sim->constants().volume, lowestPoint(out.body, side));
    out.share = submergedShare(out.body, side, level);
    out.verticalRms = std::sqrt(squares / std::max(counted, 1));
    return out;
}

TEST_F(SimulationBodies, CubesFloatAtTheDraftArchimedesGives) {
    for (float ratio : {0.5f}) {
        const Settled s = floatCube(ratio, 8 * kSpacing, ratio - 0.1f, 3);
        std::printf("ratio %.2f: submerged share %.3f, vertical rms %.4f m/s\n", ratio, s.share,
                    s.verticalRms);
        EXPECT_NEAR(s.share, ratio, 0.05);
        EXPECT_LT(s.verticalRms, 0.02);
        EXPECT_EQ(s.worstNonFinite, 0u);
        EXPECT_EQ(s.worstInside, 0u);
    }
}

} // namespace
} // namespace sluice::rt
