// Still water against walls and static colliders (docs/pbf.md, "Boundary volume"): with the
// solids' boundary volume in the density, water at rest keeps the height its volume gives and
// its first layer against a wall is as dense as the bulk.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;

constexpr float kSpacing = 0.02f;

class SimulationBoundary : public GpuTest {};

/// Still water in a tank whose inside is the box [lo, hi], measured after it settled: s is the
/// spacing, the volume height H = N s^3 / floor area. Number densities are per s^3, so a rest
/// lattice has 1 everywhere. The layers are counted from 2 s to 8 s above the floor: a corner
/// column holds one particle a spacing, so its slab's 4 x 6 particles resolve 4 % (with 3 s to
/// 7 s, 16 particles: a particle more or less moved the ratio by 6 %).
struct StillWater {
    double surfaceError = 0.0; ///< (mean highest centre of interior columns + s/2) / H - 1
    double bulk = 0.0;         ///< 3 s from every side wall, from 2 s to 8 s above the floor
    double floor = 0.0;        ///< centres within s of the floor, 3 s from the side walls
    double wall = 0.0; ///< within s of one side wall, 2 s to 8 s up, 3 s from the others; mean of 4
    double corner = 0.0; ///< within s of two side walls, 2 s to 8 s up; mean of the 4 corners
};

StillWater measure(const std::vector<ParticleState>& particles, glm::vec3 lo, glm::vec3 hi) {
    const double s = kSpacing;
    const double ax = hi.x - lo.x, az = hi.z - lo.z;
    const double height = double(particles.size()) * s * s * s / (ax * az);
    std::map<std::pair<int, int>, double> tops;
    double bulk = 0.0, floor = 0.0, walls[4] = {}, corners[4] = {};
    for (const ParticleState& p : particles) {
        const glm::dvec3 x(p.position);
        const double d[4] = {x.x - lo.x, hi.x - x.x, x.z - lo.z, hi.z - x.z}; // -x, +x, -z, +z
        const double dx = std::min(d[0], d[1]), dz = std::min(d[2], d[3]);
        const double y = x.y - lo.y;
        if (dx >= 2 * s && dz >= 2 * s) {
            const std::pair<int, int> column(int((x.x - lo.x) / s), int((x.z - lo.z) / s));
            const auto it = tops.find(column);
            tops[column] = it == tops.end() ? y : std::max(it->second, y);
        }
        const bool mid = y >= 2 * s && y < 8 * s;
        if (dx >= 3 * s && dz >= 3 * s) {
            bulk += mid ? 1.0 : 0.0;
            floor += y < s ? 1.0 : 0.0;
        }
        for (int w = 0; w < 4; ++w) {
            const double across = w < 2 ? dz : dx; // distance to the walls of the other axis
            if (mid && d[w] < s && across >= 3 * s)
                walls[w] += 1.0;
        }
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                if (mid && d[a] < s && d[2 + b] < s)
                    corners[2 * a + b] += 1.0;
    }
    double surface = 0.0;
    for (const auto& column : tops)
        surface += column.second;
    surface = surface / double(std::max<std::size_t>(tops.size(), 1)) + 0.5 * s;
    const double s3 = s * s * s;
    StillWater out;
    out.surfaceError = surface / height - 1.0;
    out.bulk = bulk * s3 / ((ax - 6 * s) * (az - 6 * s) * 6 * s);
    out.floor = floor * s3 / ((ax - 6 * s) * (az - 6 * s) * s);
    for (int w = 0; w < 4; ++w)
        out.wall += 0.25 * walls[w] * s3 / (s * ((w < 2 ? az : ax) - 6 * s) * 6 * s);
    for (int c = 0; c < 4; ++c)
        out.corner += 0.25 * corners[c] * s3 / (s * s * 6 * s);
    return out;
}

/// Water 10 spacings deep filling the inside [lo, lo + (15, 10, 15) s] of a tank, released at
/// the rest spacing with the shipped early stop and played for 3 s, deterministic.
StillWater settle(format::Scene scene, std::vector<format::ColliderAsset> assets, glm::vec3 lo,
                  glm::vec3 hi, const char* what) {
    scene.simulation.targetDensityError = 0.005f;
    SimulationOptions options;
    options.deterministic = true;
    auto sim = Simulation::create(scene, std::move(assets), options);
    EXPECT_TRUE(sim) << sim.error().message();
    if (!sim)
        return {};
    StepStats worst;
    for (int step = 0; step < 180; ++step) {
        sim->step();
        const StepStats stats = sim->readStats();
        worst.nonFinite += stats.nonFinite;
        worst.insideColliders = std::max(worst.insideColliders, stats.insideColliders);
    }
    EXPECT_EQ(worst.nonFinite, 0u) << what;
    EXPECT_EQ(worst.insideColliders, 0u) << what;
    const StillWater w = measure(sim->downloadParticles(), lo, hi);
    std::printf("%s: surface %+.2f %% of the volume's height; per s^3: bulk %.3f, floor "
                "layer %.3f, wall layer %.3f, corner column %.3f\n",
                what, 100 * w.surfaceError, w.bulk, w.floor, w.wall, w.corner);
    return w;
}

constexpr glm::uvec3 kWater(15, 10, 15);

// Issue 25's still-water figures: the surface within 2 % of the height the volume gives, and
// the first layer at the floor, at a side wall and in a corner within 10 % of the bulk's number
// density.
void expectStill(const StillWater& w, const char* what) {
    EXPECT_LT(std::abs(w.surfaceError), 0.02) << what;
    EXPECT_NEAR(w.floor / w.bulk, 1.0, 0.1) << what << ": floor layer";
    EXPECT_NEAR(w.wall / w.bulk, 1.0, 0.1) << what << ": wall layer";
    EXPECT_NEAR(w.corner / w.bulk, 1.0, 0.1) << what << ": corner column";
}

TEST_F(SimulationBoundary, StillWaterInTheDomainBoxKeepsItsVolumeAndItsWallLayers) {
    format::Scene scene = testscene::smallScene(kWater, kSpacing, 4);
    const glm::vec3 lo = *scene.domainMin, hi = *scene.domainMax;
    expectStill(settle(scene, {}, lo, hi, "domain box"), "domain box");
}

TEST_F(SimulationBoundary, StillWaterInATankColliderKeepsItsVolumeAndItsWallLayers) {
    // The tank is a static collider: the field of the box [lo, hi] turned inside out (solid
    // everywhere but the box), inside a domain box that only bounds the neighbour grid.
    format::Scene scene = testscene::smallScene(kWater, kSpacing, 4);
    const glm::vec3 lo(0.0f), hi = glm::vec3(kWater.x, 2 * kWater.y, kWater.z) * kSpacing;
    scene.domainMin = lo - glm::vec3(0.1f);
    scene.domainMax = hi + glm::vec3(0.1f);
    const glm::dvec3 dlo(lo), dhi(hi);
    std::vector<format::ColliderAsset> assets{
        testscene::assetOverBox(dlo, dhi, 0.5 * kSpacing, 0.06, [dlo, dhi](const glm::dvec3& p) {
            return -testasset::boxSdf(p, dlo, dhi);
        })};
    format::SceneCollider tank;
    tank.asset = "tank.slc";
    scene.colliders.push_back(tank);
    expectStill(settle(scene, std::move(assets), lo, hi, "tank collider"), "tank collider");
}

} // namespace
} // namespace sluice::rt
