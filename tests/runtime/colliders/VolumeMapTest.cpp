// Volume maps of static colliders (docs/pbf.md, "Volume maps"): the boundary volume the solver
// adds at a collider's edges, corners and thin walls against the share of the kernel support
// the solid really fills, integrated here by brute force; flat faces keep the closed form; the
// maps follow a change of h; the CPU reference builds the same maps.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "ReferencePbf.h"
#include "RuntimeTestScenes.h"
#include "sim/ParticleCompare.h"
#include "sluice/gpu/colliders/VolumeMap.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;

constexpr float kSpacing = 0.02f;

class VolumeMap : public GpuTest {};

using Solid = std::function<bool(const glm::dvec3&)>;

/// k times the poly6 weight of the support of radius h around x that lies in the solid: the
/// exact share the boundary volume stands for (docs/bodies.md, "Boundary volume"), by the
/// midpoint rule on 96^3 cells.
double exactShare(const Solid& solid, glm::dvec3 x, double h, double k) {
    constexpr int n = 96;
    const double d = 2.0 * h / n;
    double sum = 0.0, total = 0.0;
    for (int kz = 0; kz < n; ++kz)
        for (int ky = 0; ky < n; ++ky)
            for (int kx = 0; kx < n; ++kx) {
                const glm::dvec3 o = (glm::dvec3(kx, ky, kz) + 0.5) * d - h;
                const double a = 1.0 - glm::dot(o, o) / (h * h);
                if (a <= 0.0)
                    continue;
                const double w = a * a * a;
                total += w;
                sum += solid(x + o) ? w : 0.0;
            }
    return k * sum / total;
}

/// The closed form of a flat boundary at distance phi (docs/bodies.md): what a collider without
/// a map gives.
double flatShare(double phi, double h, double k) {
    const double u = std::clamp(phi / h, -1.0, 1.0), u2 = u * u;
    const double f = u - 4.0 / 3.0 * u * u2 + 6.0 / 5.0 * u * u2 * u2 -
                     4.0 / 7.0 * u * u2 * u2 * u2 + u * u2 * u2 * u2 * u2 / 9.0;
    return k * (0.5 - 315.0 / 256.0 * f);
}

struct Probe {
    const char* what;
    glm::vec3 x;
    double phi;       ///< the solid's distance there
    double tolerance; ///< relative, of the exact share
};

struct Case {
    format::Scene scene;
    std::vector<format::ColliderAsset> assets;
    Solid solid;
};

// A tank: solid everywhere but the box [0, 0.3]^3 (a static collider, its field turned inside
// out, sampled every `voxel`), so its inside has flat faces, concave edges and corners.
Case tankCase(double voxel = 0.5 * kSpacing) {
    Case c{testscene::emptyScene(kSpacing), {}, {}};
    const glm::dvec3 lo(0.0), hi(0.3);
    c.assets.push_back(testscene::assetOverBox(lo, hi, voxel, 0.06, [lo, hi](const glm::dvec3& p) {
        return -testasset::boxSdf(p, lo, hi);
    }));
    format::SceneCollider tank;
    tank.asset = "tank.slc";
    c.scene.colliders.push_back(tank);
    c.solid = [lo, hi](const glm::dvec3& p) { return testasset::boxSdf(p, lo, hi) > 0.0; };
    return c;
}

// A cube [0, 0.2]^3 (convex edges) and, apart from it, a plate half a spacing thick with fluid
// on both sides (a thin wall).
Case cubeAndPlateCase() {
    Case c{testscene::emptyScene(kSpacing), {}, {}};
    const glm::dvec3 cubeLo(0.0), cubeHi(0.2);
    const glm::dvec3 plateLo(0.5, 0.0, 0.0), plateHi(0.8, 0.5 * kSpacing, 0.3);
    c.assets.push_back(testscene::boxColliderAsset(cubeLo, cubeHi, 0.5 * kSpacing));
    // A wall one voxel thick has no grid point inside it, so its field never goes negative:
    // the plate is sampled at a quarter spacing, two voxels through.
    c.assets.push_back(testscene::boxColliderAsset(plateLo, plateHi, 0.25 * kSpacing));
    for (const char* name : {"cube.slc", "plate.slc"}) {
        format::SceneCollider collider;
        collider.asset = name;
        c.scene.colliders.push_back(collider);
    }
    c.solid = [=](const glm::dvec3& p) {
        return testasset::boxSdf(p, cubeLo, cubeHi) < 0.0 ||
               testasset::boxSdf(p, plateLo, plateHi) < 0.0;
    };
    return c;
}

// Probes the solver's share at each point against the exact one; returns the shares.
std::vector<glm::vec4> expectShares(Simulation& sim, const Solid& solid,
                                    const std::vector<Probe>& probes) {
    const double h = sim.constants().h, k = sim.constants().boundaryScale;
    std::vector<glm::vec3> points;
    for (const Probe& p : probes)
        points.push_back(p.x);
    auto shares = sim.solidBoundaryAt(points);
    EXPECT_TRUE(bool(shares)) << (shares ? "" : shares.error().detail);
    if (!shares)
        return {};
    for (std::size_t i = 0; i < probes.size(); ++i) {
        const double exact = exactShare(solid, glm::dvec3(probes[i].x), h, k);
        const double flat = flatShare(probes[i].phi, h, k);
        std::printf(
            "  %-28s exact %.4f  solver %.4f (%+.1f %%)  flat closed form %.4f (%+.1f %%)\n",
            probes[i].what, exact, (*shares)[i].w, 100.0 * ((*shares)[i].w / exact - 1.0), flat,
            100.0 * (flat / exact - 1.0));
        // Small shares to 0.01 of the rest density: the closed form is 0.075 off on the convex
        // edge.
        const double allowed = std::max(probes[i].tolerance * exact, exact < 0.05 ? 0.01 : 0.0);
        EXPECT_NEAR((*shares)[i].w, exact, allowed) << probes[i].what;
    }
    return *shares;
}

TEST_F(VolumeMap, TheTanksFacesEdgesAndCornersGetTheShareTheirSolidFills) {
    Case c = tankCase();
    auto sim = Simulation::create(c.scene, std::move(c.assets));
    ASSERT_TRUE(sim) << sim.error().detail;
    EXPECT_EQ(sim->volumeMapCount(), 1u);
    const float r = 0.5f * kSpacing, m = 0.15f;
    // At the rest distance r from each wall faced. The flat closed form is 44 % and 59 % short
    // in the edge and the corner (docs/pbf.md, "Kernel shares").
    const std::vector<Probe> probes = {
        {"floor", {m, r, m}, r, 0.01},
        {"floor, 3/4 h up", {m, 0.75f * 2 * kSpacing, m}, 0.75 * 2 * kSpacing, 0.05},
        {"concave edge", {r, r, m}, r, 0.04},
        {"corner", {r, r, r}, r, 0.05},
        {"corner, 1.5 r out", {3 * r, 3 * r, 3 * r}, 3 * r, 0.05},
    };
    expectShares(*sim, c.solid, probes);
}

TEST_F(VolumeMap, ConvexEdgesAndThinWallsGetTheShareTheirSolidFills) {
    Case c = cubeAndPlateCase();
    auto sim = Simulation::create(c.scene, std::move(c.assets));
    ASSERT_TRUE(sim) << sim.error().detail;
    EXPECT_EQ(sim->volumeMapCount(), 2u);
    const float r = 0.5f * kSpacing;
    // The flat closed form is 29 % over on the thin wall and three times the share on the
    // convex edge (docs/pbf.md, "Kernel shares").
    const std::vector<Probe> probes = {
        {"cube top", {0.1f, 0.2f + r, 0.1f}, r, 0.01},
        {"convex edge", {0.2f + r, 0.2f + r, 0.1f}, std::sqrt(2.0) * r, 0.05},
        {"thin wall, above", {0.65f, kSpacing * 0.5f + r, 0.15f}, r, 0.05},
        {"thin wall, below", {0.65f, -r, 0.15f}, r, 0.05},
    };
    expectShares(*sim, c.solid, probes);
}

TEST_F(VolumeMap, TheShareGradientIsTheSlopeOfTheShare) {
    Case c = tankCase();
    auto sim = Simulation::create(c.scene, std::move(c.assets));
    ASSERT_TRUE(sim) << sim.error().detail;
    // Central differences of the probed share along each axis, in an edge and a corner where
    // the map carries most of the share, against the probed gradient.
    const float e = 0.002f;
    for (const glm::vec3 x :
         {glm::vec3(0.013f, 0.011f, 0.15f), glm::vec3(0.012f, 0.014f, 0.011f)}) {
        std::vector<glm::vec3> points{x};
        for (int a = 0; a < 3; ++a) {
            glm::vec3 d(0.0f);
            d[a] = e;
            points.push_back(x + d);
            points.push_back(x - d);
        }
        auto shares = sim->solidBoundaryAt(points);
        ASSERT_TRUE(shares) << shares.error().detail;
        const glm::vec3 gradient((*shares)[0]);
        for (int a = 0; a < 3; ++a) {
            const float slope = ((*shares)[1 + 2 * a].w - (*shares)[2 + 2 * a].w) / (2 * e);
            EXPECT_NEAR(gradient[a], slope, 0.1f * glm::length(gradient)) << "axis " << a;
        }
        EXPECT_GT(glm::length(gradient), 1.0f); // the share changes by tenths over h
    }
}

TEST_F(VolumeMap, TheMapsFollowAChangeOfTheKernelRadius) {
    Case c = tankCase();
    auto sim = Simulation::create(c.scene, std::move(c.assets));
    ASSERT_TRUE(sim) << sim.error().detail;
    format::SimulationParams p = sim->parameters();
    p.kernelRadius = 3.0f * kSpacing;
    ASSERT_TRUE(sim->setParameters(p));
    const float r = 0.5f * kSpacing, m = 0.15f;
    expectShares(
        *sim, c.solid,
        {{"floor at h = 3 s", {m, r, m}, r, 0.01}, {"corner at h = 3 s", {r, r, r}, r, 0.05}});
}

TEST_F(VolumeMap, MapsThatWouldNotFitTheGridsStorageBlockLeaveTheClosedForm) {
    // Two boxes whose grids fill 60 % of the GL's largest storage block (128 MiB on llvmpipe):
    // their maps would take as much again, so neither gets one and the scene still loads.
    GLint64 block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    const double pointsEach = 0.3 * double(block) / sizeof(float);
    if (pointsEach > 12.0e6)
        GTEST_SKIP() << "storage blocks of " << block << " bytes: the grids would be too large";
    const double side = std::cbrt(pointsEach);
    format::Scene scene = testscene::emptyScene(kSpacing);
    std::vector<format::ColliderAsset> assets;
    for (int b = 0; b < 2; ++b) {
        const glm::dvec3 lo(2.0 * b, 0.0, 0.0), hi = lo + glm::dvec3(0.5);
        assets.push_back(testscene::assetFromSdf(
            glm::uvec3(glm::uint(side)), lo - glm::dvec3(0.1), 0.7 / side,
            [lo, hi](const glm::dvec3& p) { return testasset::boxSdf(p, lo, hi); }));
        format::SceneCollider box;
        box.asset = "box.slc";
        scene.colliders.push_back(box);
    }
    auto sim = Simulation::create(scene, std::move(assets));
    ASSERT_TRUE(sim) << sim.error().detail;
    EXPECT_EQ(sim->volumeMapCount(), 0u);
    // The closed form on a convex edge: three times the exact share (the table of docs/pbf.md).
    const float r = 0.5f * kSpacing;
    auto shares = sim->solidBoundaryAt({glm::vec3(0.5f + r, 0.5f + r, 0.25f)});
    ASSERT_TRUE(shares);
    const double k = sim->constants().boundaryScale, h = sim->constants().h;
    EXPECT_NEAR((*shares)[0].w, flatShare(std::sqrt(2.0) * r, h, k), 0.002);
}

// The tank with a block of water, 6 x 5 x 6 particles, in its corner (180 particles).
Case cornerCase(double voxel) {
    Case c = tankCase(voxel);
    format::FluidBlock block;
    block.min = glm::vec3(0.0f);
    block.max = glm::vec3(0.12f, 0.1f, 0.12f);
    c.scene.blocks.push_back(block);
    c.scene.simulation.capacity = 6 * 5 * 6;
    c.scene.domainMin = glm::vec3(-0.1f);
    c.scene.domainMax = glm::vec3(0.4f);
    return c;
}

// A block of water in a corner of the tank, where the maps carry most of the walls' share: one
// step of the GPU solver against the CPU reference, which builds the same maps in double
// (tests/reference/ReferenceVolumeMap.cpp). Without the reference's maps the particles differ by
// 0.013 h. At a grid of h / 4 the quadrature reads the field trilinearly, at h / 5.3 it reads the
// grid's values (pbf_volume_map.comp).
void expectCornerParity(double voxel) {
    Case c = cornerCase(voxel);
    std::vector<ref::ReferenceCollider> refColliders{{&c.assets[0], c.scene.colliders[0]}};
    ref::ReferencePbf cpu(c.scene, refColliders);
    SimulationOptions options;
    options.deterministic = true;
    auto gpu = Simulation::create(c.scene, c.assets, options);
    ASSERT_TRUE(gpu) << gpu.error().message();
    ASSERT_EQ(gpu->volumeMapCount(), 1u);
    ASSERT_EQ(gpu->particleCount(), 180u);
    ASSERT_EQ(cpu.particles().size(), 180u);
    gpu->step();
    cpu.step();
    const double h = c.scene.simulation.kernelRadius;
    const double afterOne = test::maxPositionDifference(gpu->downloadParticles(), cpu.particles());
    std::printf("  after one step: max |x_gpu - x_cpu| = %.3g h\n", afterOne / h);
    EXPECT_LT(afterOne, 1e-4 * h);
    const StepStats stats = gpu->readStats();
    EXPECT_NEAR(stats.avgDensityError, cpu.stats().avgDensityError, 1e-4);
    EXPECT_NEAR(stats.maxDensityError, cpu.stats().maxDensityError, 1e-3);
}

// The passes fetch the grid and its map through the SDF buffer's texel view, or read them from
// the storage block where the buffer is past the GL's texel-buffer limit: the same bits.
TEST_F(VolumeMap, TheStorageReadsGiveTheTexelViewsBits) {
    std::vector<ParticleState> runs[2];
    for (int fromStorage = 0; fromStorage < 2; ++fromStorage) {
        Case c = cornerCase(0.5 * kSpacing);
        SimulationOptions options;
        options.deterministic = true;
        options.sdfFromStorage = fromStorage != 0;
        auto sim = Simulation::create(c.scene, c.assets, options);
        ASSERT_TRUE(sim) << sim.error().message();
        ASSERT_EQ(sim->volumeMapCount(), 1u);
        for (int step = 0; step < 5; ++step)
            sim->step();
        runs[fromStorage] = sim->downloadParticles();
    }
    ASSERT_EQ(runs[0].size(), 180u);
    // A view that read nothing (an unbound unit reads zeros) would put the walls elsewhere: the
    // water in the corner leans on them from the first substep.
    EXPECT_EQ(test::differingParticles(runs[0], runs[1]), 0u);
}

TEST_F(VolumeMap, WaterInTheTanksCornerMatchesTheCpuReference) {
    expectCornerParity(0.5 * kSpacing);
}

TEST_F(VolumeMap, WaterInTheTanksCornerMatchesTheCpuReferenceOnAFineGrid) {
    expectCornerParity(0.375 * kSpacing);
}

TEST_F(VolumeMap, AMapBakedWithTheColliderIsTheOneTheSceneBuilds) {
    Case c = cubeAndPlateCase();
    auto built = Simulation::create(c.scene, c.assets);
    ASSERT_TRUE(built) << built.error().detail;
    VolumeMapLoad load = built->volumeMapLoad();
    EXPECT_EQ(load.built, 2u);
    EXPECT_EQ(load.baked, 0u);
    EXPECT_EQ(load.builtFor, (std::vector<std::uint32_t>{0, 1}));
    EXPECT_GT(load.seconds, 0.0);

    // The cube's map baked for the scene's h; the plate's for another support only.
    const double h = double(built->constants().h);
    std::vector<format::ColliderAsset> assets = c.assets;
    auto cubeMap = gpu::computeVolumeMap(assets[0], h);
    ASSERT_TRUE(cubeMap) << cubeMap.error().message();
    EXPECT_GT(std::count_if(cubeMap->begin(), cubeMap->end(), [](float v) { return v != 0.0f; }),
              100); // its edges and corners
    assets[0].volumeMaps.push_back({h, *cubeMap});
    auto plateMap = gpu::computeVolumeMap(assets[1], 2.0 * h);
    ASSERT_TRUE(plateMap) << plateMap.error().message();
    assets[1].volumeMaps.push_back({2.0 * h, *plateMap});
    auto baked = Simulation::create(c.scene, assets);
    ASSERT_TRUE(baked) << baked.error().detail;
    load = baked->volumeMapLoad();
    EXPECT_EQ(load.baked, 1u);
    EXPECT_EQ(load.built, 1u);
    EXPECT_EQ(load.builtFor, (std::vector<std::uint32_t>{1}));

    // Every share around the cube's edges and corners and the plate, bit for bit.
    std::vector<glm::vec3> points;
    for (float x = -0.03f; x <= 0.83f; x += 0.007f)
        for (float y = -0.03f; y <= 0.23f; y += 0.005f)
            points.push_back({x, y, 0.2f - 0.3f * x});
    auto fromBuilt = built->solidBoundaryAt(points);
    auto fromBaked = baked->solidBoundaryAt(points);
    ASSERT_TRUE(fromBuilt && fromBaked);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
        differ += (*fromBuilt)[i] != (*fromBaked)[i];
    EXPECT_EQ(differ, 0u) << "of " << points.size() << " points";

    // The baked map is what the scene reads: one changed by a tenth moves the shares near the
    // cube's edges.
    for (float& v : assets[0].volumeMaps[0].values)
        v = v != 0.0f ? v + 0.1f : v;
    auto altered = Simulation::create(c.scene, assets);
    ASSERT_TRUE(altered) << altered.error().detail;
    auto fromAltered = altered->solidBoundaryAt(points);
    ASSERT_TRUE(fromAltered);
    differ = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
        differ += (*fromBuilt)[i] != (*fromAltered)[i];
    EXPECT_GT(differ, 10u);

    EXPECT_EQ(gpu::computeVolumeMap(assets[0], 0.0).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(gpu::computeVolumeMap(assets[0], std::nan("")).error().code,
              ErrorCode::InvalidArgument);
}

} // namespace
} // namespace sluice::rt
