// Scenes with sparse colliders on the GPU solver: the same tank baked dense and sparse on one
// grid gives the same run, bit for bit; the level-scale terrain (a sparse bake of the build)
// catches the water it pours, with no particle inside it and none non-finite.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "ProgramRun.h"
#include "ReferencePbf.h"
#include "sim/ParticleCompare.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

namespace fs = std::filesystem;

const fs::path kAssets = SLUICE_BUILD_ASSETS_DIR; // scenes and baked colliders, side by side

using testrun::tempDir;

/// Bakes tank.obj into dir/name with the CGAL backend at the tank scene's 7.5 mm voxels and
/// `extra` arguments.
void bakeTank(const fs::path& dir, const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"bake",          (fs::path(SLUICE_SOURCE_DIR) / "assets" /
                                                       "tank.obj").string(),
                                     "-o",            (dir / name).string(),
                                     "--backend",     "cgal",
                                     "--voxel-size",  "0.0075",
                                     "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const testrun::RunResult run = testrun::runProgram(SLUICE_BAKE_EXE, dir, args);
    ASSERT_EQ(run.code, 0) << testrun::shown(run);
}

/// The drop scene's pool and falling ball in the tank, naming `asset` as its collider.
format::Scene dropScene(const fs::path& dir, const std::string& asset) {
    std::ifstream in(kAssets / "drop.json");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string from = "\"tank.slc\"";
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos);
    text.replace(at, from.size(), "\"" + asset + "\"");
    const fs::path path = dir / ("drop-" + asset + ".json");
    std::ofstream(path, std::ios::binary) << text;
    auto scene = format::readScene(path);
    EXPECT_TRUE(scene.ok()) << scene.error().message();
    return scene.ok() ? *scene : format::Scene{};
}

using SparseScene = gpu::test::GpuTest;

/// The drop scene in the tank baked dense and sparse on one grid, played 15 steps each: returns
/// the particles' differing positions at the end (the dense bake asked for the padding the
/// sparse one raises to, band + 1, so both sample the same grid points).
std::size_t denseAndSparseDiffer(const char* name, int band) {
    const fs::path dir = tempDir(name);
    bakeTank(dir, "dense.slc", {"--padding", std::to_string(band + 1)});
    bakeTank(dir, "sparse.slc", {"--sparse", "--band", std::to_string(band)});
    std::vector<std::vector<ParticleState>> finals;
    for (const char* asset : {"dense.slc", "sparse.slc"}) {
        format::Scene scene = dropScene(dir, asset);
        scene.simulation.maxIterations = 3;
        auto colliders = loadSceneColliders(scene);
        EXPECT_TRUE(colliders) << colliders.error().message();
        if (!colliders)
            return ~std::size_t(0);
        EXPECT_EQ((*colliders)[0].sparse(), std::string(asset) == "sparse.slc");
        SimulationOptions options;
        options.deterministic = true;
        auto sim = Simulation::create(scene, std::move(*colliders), options);
        EXPECT_TRUE(sim) << sim.error().message();
        if (!sim)
            return ~std::size_t(0);
        for (int step = 1; step <= 15; ++step) {
            sim->step();
            const StepStats stats = sim->readStats();
            EXPECT_EQ(stats.insideColliders, 0u) << asset << " step " << step;
            EXPECT_EQ(stats.nonFinite, 0u) << asset << " step " << step;
        }
        std::vector<ParticleState> particles = sim->downloadParticles();
        std::sort(particles.begin(), particles.end(),
                  [](const ParticleState& a, const ParticleState& b) { return a.id < b.id; });
        finals.push_back(std::move(particles));
    }
    EXPECT_EQ(finals[0].size(), finals[1].size());
    EXPECT_GT(finals[0].size(), 3000u);
    std::size_t differing = 0;
    for (std::size_t n = 0; n < std::min(finals[0].size(), finals[1].size()); ++n)
        differing += std::memcmp(&finals[0][n].position, &finals[1][n].position,
                                 sizeof(glm::vec3)) != 0;
    return differing;
}

TEST_F(SparseScene, TheTankBakedDenseAndSparseOnOneGridPlaysTheSameRunBitForBit) {
    // The boundary volume reads the tank's phi up to h = 4 cm (docs/pbf.md, "Boundary volume"),
    // exact in a band of 8 voxels of 7.5 mm (4 cm / 7.5 mm + sqrt(3) = 7.07): the sparse path of
    // the boundary volume gives the dense one's bits. (With a 5-voxel band every particle's
    // bits differed after 15 steps: the share past the band is left out, docs/pbf.md.)
    EXPECT_EQ(denseAndSparseDiffer("sparse-scene-tank", 8), 0u);
}

// The boundary share at points of the tank's inside corner at (-0.37, 0.03, -0.22)
// and along its floor's edge, 0 to 6 cm from the walls every 5 mm, from the tank baked dense and
// sparse (band 8 voxels) on one grid: both get a volume map, and the sparse one (per leaf) gives
// the dense one's values where a particle can be.
TEST_F(SparseScene, TheSparseTanksVolumeMapGivesTheDenseOnesShares) {
    const fs::path dir = tempDir("sparse-scene-tank-map");
    bakeTank(dir, "dense.slc", {"--padding", "9"});
    bakeTank(dir, "sparse.slc", {"--sparse", "--band", "8"});
    std::vector<glm::vec3> points;
    for (int k = 0; k <= 12; ++k)
        for (int j = 0; j <= 12; ++j)
            for (int i = 0; i <= 12; ++i) {
                points.emplace_back(-0.365f + 0.005f * i, 0.035f + 0.005f * j,
                                    -0.215f + 0.005f * k);
                points.emplace_back(0.1f + 0.005f * i, 0.035f + 0.005f * j, -0.215f + 0.005f * k);
            }
    std::vector<std::vector<glm::vec4>> shares;
    for (const char* asset : {"dense.slc", "sparse.slc"}) {
        format::Scene scene = dropScene(dir, asset);
        auto colliders = loadSceneColliders(scene);
        ASSERT_TRUE(colliders) << colliders.error().message();
        auto sim = Simulation::create(scene, std::move(*colliders));
        ASSERT_TRUE(sim) << sim.error().message();
        EXPECT_EQ(sim->volumeMapCount(), 1u) << asset;
        auto at = sim->solidBoundaryAt(points);
        ASSERT_TRUE(at) << at.error().message();
        shares.push_back(std::move(*at));
    }
    double worst = 0.0, corner = 0.0;
    for (std::size_t n = 0; n < points.size(); ++n) {
        worst = std::max(worst, double(std::abs(shares[1][n].w - shares[0][n].w)));
        corner = std::max(corner, double(shares[0][n].w));
    }
    std::printf("  dense share up to %.4f; sparse against dense: max |difference| %.3g\n", corner,
                worst);
    EXPECT_GT(corner, 0.3); // the corner's three walls: the map is in the probes' reach
    EXPECT_EQ(worst, 0.0); // the same quadrature of the same values
}

// A block of water in the sparse tank's corner, where its volume map carries most of the walls'
// share: one step of the GPU solver against the CPU reference, which builds the sparse map in
// double by the same rule (tests/reference/ReferenceVolumeMap.cpp, at the leaves' voxels).
TEST_F(SparseScene, WaterInTheSparseTanksCornerMatchesTheCpuReference) {
    const fs::path dir = tempDir("sparse-scene-tank-parity");
    bakeTank(dir, "sparse.slc", {"--sparse", "--band", "8"});
    format::Scene scene = dropScene(dir, "sparse.slc");
    scene.blocks.clear();
    format::FluidBlock block;
    block.min = glm::vec3(-0.37f, 0.03f, -0.22f);
    block.max = glm::vec3(-0.25f, 0.13f, -0.10f);
    scene.blocks.push_back(block);
    scene.simulation.capacity = 6 * 5 * 6;
    auto colliders = loadSceneColliders(scene);
    ASSERT_TRUE(colliders) << colliders.error().message();
    ASSERT_TRUE((*colliders)[0].sparse());
    std::vector<ref::ReferenceCollider> refColliders{{&(*colliders)[0], scene.colliders[0]}};
    ref::ReferencePbf cpu(scene, refColliders);
    SimulationOptions options;
    options.deterministic = true;
    auto gpu = Simulation::create(scene, *colliders, options);
    ASSERT_TRUE(gpu) << gpu.error().message();
    ASSERT_EQ(gpu->volumeMapCount(), 1u);
    ASSERT_EQ(gpu->particleCount(), 180u);
    ASSERT_EQ(cpu.particles().size(), 180u);
    // The share itself, at points across the corner every 2.5 mm (the map's ridge along each
    // edge's diagonal included, where the field's gradient vanishes).
    std::vector<glm::vec3> points;
    for (int k = 0; k < 16; ++k)
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i)
                points.emplace_back(-0.3675f + 0.0025f * i, 0.0325f + 0.0025f * j,
                                    -0.2175f + 0.0025f * k);
    auto shares = gpu->solidBoundaryAt(points);
    ASSERT_TRUE(shares) << shares.error().message();
    double worst = 0.0;
    for (std::size_t n = 0; n < points.size(); ++n)
        worst = std::max(worst,
                         double(std::abs((*shares)[n].w - cpu.solidBoundaryAt(points[n]).w)));
    std::printf("  share: max |gpu - cpu| = %.3g\n", worst);
    EXPECT_LT(worst, 1e-5);
    gpu->step();
    cpu.step();
    const double h = scene.simulation.kernelRadius;
    const double afterOne = test::maxPositionDifference(gpu->downloadParticles(), cpu.particles());
    std::printf("  after one step: max |x_gpu - x_cpu| = %.3g h\n", afterOne / h);
    EXPECT_LT(afterOne, 1e-4 * h);
    EXPECT_NEAR(gpu->readStats().avgDensityError, cpu.stats().avgDensityError, 1e-4);
}

TEST_F(SparseScene, ALargerKernelRadiusIsRefusedWhenADynamicBodysBandCannotHoldIt) {
    // The committed sparse sphere (band 2 voxels of 0.05 m, radius 0.2 m) as a body, with the
    // mass properties a closed mesh's bake stores. At 6 mm spacing and h = 12 mm its boundary
    // reads phi up to h + 0.05 spacing = 12.3 mm: 0.25 + sqrt(3) = 1.98 voxels, inside the band.
    const fs::path dir = tempDir("sparse-body-h");
    auto asset = format::readAsset(fs::path(SLUICE_SOURCE_DIR) /
                                   "tests/fuzz/corpus/asset_reader/sphere-sparse.slc");
    ASSERT_TRUE(asset) << asset.error().message();
    const double r = 0.2, volume = 4.0 / 3.0 * 3.141592653589793 * r * r * r;
    asset->meta.meshMass =
        format::MassProperties{volume, glm::dvec3(0.0), glm::dmat3(0.4 * volume * r * r)};
    ASSERT_TRUE(format::writeAsset(dir / "ball.slc", *asset));
    std::ofstream(dir / "scene.json") << R"({ "simulation": { "spacing": 0.006 },
  "fluid": [ { "box": { "min": [0.3, 0.3, 0.3], "max": [0.33, 0.33, 0.33] } } ],
  "colliders": [ { "asset": "ball.slc", "dynamic": { "density": 500 } } ] })";
    auto scene = format::readScene(dir / "scene.json");
    ASSERT_TRUE(scene) << scene.error().message();
    auto colliders = loadSceneColliders(*scene);
    ASSERT_TRUE(colliders) << colliders.error().message();
    auto sim = Simulation::create(*scene, std::move(*colliders));
    ASSERT_TRUE(sim) << sim.error().message();

    // h = 18 mm reads 18.3 mm: 2.1 voxels, past the band. Refused, nothing changed.
    format::SimulationParams wide = sim->parameters();
    wide.kernelRadius = 0.018f;
    auto refused = sim->setParameters(wide);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(refused.error().detail.find("--sparse --band 3"), std::string::npos)
        << refused.error().detail;
    EXPECT_FLOAT_EQ(sim->parameters().kernelRadius, 0.012f);
    // A smaller h reads less: accepted.
    format::SimulationParams narrow = sim->parameters();
    narrow.kernelRadius = 0.011f;
    EXPECT_TRUE(sim->setParameters(narrow));
    EXPECT_FLOAT_EQ(sim->parameters().kernelRadius, 0.011f);
}

TEST_F(SparseScene, TheLevelScaleTerrainCatchesThePouredWaterWithNoneInsideIt) {
#if !SLUICE_LEVEL_ASSETS
    GTEST_SKIP() << "this preset does not bake the terrain (SLUICE_BAKE_LEVEL_ASSETS=OFF)";
#endif
    auto scene = format::readScene(kAssets / "terrain.json");
    ASSERT_TRUE(scene) << scene.error().message();
    auto colliders = loadSceneColliders(*scene);
    ASSERT_TRUE(colliders) << colliders.error().message();
    const format::ColliderAsset terrain = (*colliders)[0];
    // A dense grid of the terrain's resolution would not fit one storage block on llvmpipe.
    EXPECT_GT(terrain.pointCount(), 33554432u);
    scene->simulation.maxIterations = 3;
    auto sim = Simulation::create(*scene, std::move(*colliders));
    ASSERT_TRUE(sim) << sim.error().message();
    for (int step = 1; step <= 30; ++step) {
        sim->step();
        const StepStats stats = sim->readStats();
        ASSERT_EQ(stats.insideColliders, 0u) << "step " << step;
        ASSERT_EQ(stats.nonFinite, 0u) << "step " << step;
    }
    // The CPU sampler agrees: every particle at least half a radius outside the terrain, and
    // the water has reached it (particles in contact, phi within a spacing).
    const format::SdfSampler sampler(terrain);
    const float radius = scene->simulation.spacing / 2;
    const std::vector<ParticleState> particles = sim->downloadParticles();
    ASSERT_GT(particles.size(), 300u); // 0.5 s of the nozzle
    std::size_t touching = 0;
    float deepest = 1e9f;
    for (const ParticleState& p : particles) {
        const float phi = sampler.value(glm::dvec3(p.position));
        deepest = std::min(deepest, phi);
        touching += phi < 2.0f * radius ? 1 : 0;
    }
    EXPECT_GE(deepest, -0.5f * radius);
    EXPECT_GT(touching, 50u) << "the water has not reached the terrain";
}

} // namespace
} // namespace sluice::rt
