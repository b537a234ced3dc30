// sluice-play end to end: the shipped scenes with their build-baked colliders, determinism of
// statistics and PLY files, and bad scenes failing with exit code 2 and a message that says where.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "GpuTest.h"
#include "ProgramRun.h"
#include "ShippedScenes.h"
#include "shared/Pbf.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

namespace fs = std::filesystem;
using testrun::runProgram;
using testrun::shown;

const fs::path kAssets = SLUICE_BUILD_ASSETS_DIR; // scenes and baked colliders, side by side

using testrun::tempDir;

testrun::RunResult play(const fs::path& dir, const std::vector<std::string>& args) {
    return runProgram(SLUICE_PLAY_EXE, dir, args);
}

void writeText(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

class ShippedScene : public gpu::test::GpuTest,
                     public ::testing::WithParamInterface<const char*> {};

// Every shipped scene, shortened: no particle ever inside a collider, none non-finite.
TEST_P(ShippedScene, KeepsEveryParticleOutOfCollidersAndFinite) {
    auto scene = format::readScene(kAssets / GetParam());
    ASSERT_TRUE(scene) << scene.error().message();
    auto colliders = loadSceneColliders(*scene);
    ASSERT_TRUE(colliders) << colliders.error().message();
    // Fewer iterations keep llvmpipe quick; the solver still runs and collides every substep.
    scene->simulation.maxIterations = std::min(scene->simulation.maxIterations, 3u);
    scene->simulation.minIterations = std::min(scene->simulation.minIterations, 2u);
    auto sim = Simulation::create(*scene, std::move(*colliders));
    ASSERT_TRUE(sim) << sim.error().message();
    const int steps = std::string(GetParam()) == "funnel.json" ? 40 : 12;
    for (int step = 1; step <= steps; ++step) {
        sim->step();
        const StepStats stats = sim->readStats();
        ASSERT_EQ(stats.insideColliders, 0u) << "step " << step;
        ASSERT_EQ(stats.nonFinite, 0u) << "step " << step;
    }
    EXPECT_GT(sim->particleCount(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Assets, ShippedScene, test::shippedScenes(), test::ShippedSceneName{});

TEST(SluicePlay, DeterministicRunsWriteIdenticalStatisticsAndPlyFiles) {
    const fs::path dir = tempDir("deterministic");
    std::string bytes[2][3];
    for (int run = 0; run < 2; ++run) {
        const fs::path out = dir / ("run" + std::to_string(run));
        fs::create_directories(out);
        const auto result = play(out, {(kAssets / "martin-moyce.json").string(), "--headless",
                                       "--steps", "6", "--deterministic", "--stats-every", "1",
                                       "--stats-json", (out / "stats.json").string(), "--dump-ply",
                                       (out / "ply").string(), "--dump-every", "3"});
        ASSERT_EQ(result.code, 0) << shown(result);
        bytes[run][0] = testrun::readText(out / "stats.json");
        bytes[run][1] = testrun::readText(out / "ply" / "frame_000003.ply");
        bytes[run][2] = testrun::readText(out / "ply" / "frame_000006.ply");
        EXPECT_TRUE(fs::exists(out / "ply" / "frame_000000.ply"));
        EXPECT_FALSE(fs::exists(out / "ply" / "frame_000001.ply"));
    }
    for (int f = 0; f < 3; ++f) {
        ASSERT_FALSE(bytes[0][f].empty()) << "file " << f;
        EXPECT_TRUE(bytes[0][f] == bytes[1][f]) << "file " << f << " differs between runs";
    }
    // The statistics file holds one record per step, and the PLY file one vertex per particle.
    const auto stats = nlohmann::json::parse(bytes[0][0]);
    ASSERT_EQ(stats["steps"].size(), 6u);
    const std::uint32_t particles = stats["steps"][5]["particles"];
    EXPECT_NE(bytes[0][2].find("element vertex " + std::to_string(particles) + "\n"),
              std::string::npos);
    const std::size_t header = bytes[0][2].find("end_header\n") + 11;
    EXPECT_EQ(bytes[0][2].size() - header, std::size_t(particles) * 28);
    EXPECT_FALSE(stats.contains("timing")); // wall and GPU times differ run to run
}

TEST(SluicePlay, PrintsTheStatisticsTableAndTimings) {
    const fs::path dir = tempDir("table");
    const auto result = play(dir, {(kAssets / "martin-moyce.json").string(), "--headless",
                                   "--steps", "2", "--stats-json", (dir / "s.json").string()});
    ASSERT_EQ(result.code, 0) << shown(result);
    EXPECT_NE(result.out.find("avg err %"), std::string::npos) << result.out;
    EXPECT_NE(result.out.find("steps/s"), std::string::npos) << result.out;
    const auto stats = nlohmann::json::parse(testrun::readText(dir / "s.json"));
    EXPECT_GT(stats["timing"]["stepsPerSecond"].get<double>(), 0.0);
    EXPECT_TRUE(stats["timing"]["gpuMsPerStep"].contains("solve"));
}

// --bench's memory per particle counts the hash table and the mask: 132 bytes of particle
// arrays (the vorticity shares an idle position buffer), the 48-byte neighbour mask, and
// cellCount + cellStart (8 bytes x max(1024, bit_ceil(2 capacity)) buckets, and cellStart's
// end) over the capacity. It also reports the GPU commands a substep queues.
TEST(SluicePlay, BenchCountsTheHashTableAndTheNeighbourMaskInTheBytesPerParticle) {
    const fs::path dir = tempDir("bench");
    const fs::path scenePath = kAssets / "martin-moyce.json";
    auto scene = format::readScene(scenePath);
    ASSERT_TRUE(scene) << scene.error().message();
    const std::uint64_t capacity = scene->simulation.capacity;
    ASSERT_GT(capacity, 512u);
    std::uint64_t buckets = 1024;
    while (buckets < 2 * capacity)
        buckets *= 2;
    const std::uint64_t mask = 4 * shared::kNeighbourMaskWords;
    const std::uint64_t expected = 132 + mask + (8 * buckets + 4 + capacity - 1) / capacity;
    const auto result = play(dir, {scenePath.string(), "--headless", "--bench", "--warmup", "1",
                                   "--steps", "2", "--bench-json", (dir / "b.json").string()});
    ASSERT_EQ(result.code, 0) << shown(result);
    const auto bench = nlohmann::json::parse(testrun::readText(dir / "b.json"));
    EXPECT_EQ(bench["bytesPerParticle"].get<std::uint64_t>(), expected);
    EXPECT_GE(expected, 148u + mask);
    EXPECT_LE(expected, 164u + mask);
    EXPECT_LE(expected, 212u);
    EXPECT_NE(result.out.find("(" + std::to_string(expected) +
                              " per particle of capacity, hash table and neighbour mask included"),
              std::string::npos)
        << result.out;
    EXPECT_GE(bench["gpuBytes"].get<std::uint64_t>(), expected * capacity - capacity);
    // Counted commands (SimulationCommands pins them pass by pass): 8 iterations of two
    // dispatches, the scan's two (the grid has more cells than one block), predict, the
    // scatter-reorder, vorticity and confinement, and the step statistics' share; fewer run.
    const double issued = bench["dispatchesPerSubstep"].get<double>();
    const double ran = bench["dispatchesRunPerSubstep"].get<double>();
    const double substeps = bench["substeps"].get<double>();
    EXPECT_NEAR(issued, 6.0 + 2.0 * scene->simulation.maxIterations + 1.0 / substeps, 1e-9)
        << bench["neighbourGrid"];
    EXPECT_GE(ran, 6.0 + 2.0 * 3.0);
    EXPECT_LT(ran, issued);
    EXPECT_NEAR(bench["barriersPerSubstep"].get<double>(), issued + 1.0 / substeps, 1e-9);
    EXPECT_NE(result.out.find("GPU commands per substep"), std::string::npos) << result.out;
}

struct BadScene {
    const char* name;
    const char* json;          // the scene text; "{assets}" is replaced by the assets folder
    const char* expectInError; // a piece of the message that says what and where
};

class SluicePlayBadScene : public ::testing::TestWithParam<BadScene> {};

TEST_P(SluicePlayBadScene, FailsWithExitCodeTwoAndSaysWhereAndWhy) {
    const BadScene& bad = GetParam();
    const fs::path dir = tempDir(std::string("bad-") + bad.name);
    std::string text = bad.json;
    const std::string token = "{assets}";
    for (std::size_t at; (at = text.find(token)) != std::string::npos;)
        text.replace(at, token.size(), kAssets.string());
    const fs::path scene = dir / "bad.json";
    writeText(scene, text);
    writeText(dir / "garbage.slc", "not a collider asset at all");
    const auto result = play(dir, {scene.string(), "--headless", "--steps", "1"});
    EXPECT_EQ(result.code, 2) << shown(result);
    EXPECT_NE(result.err.find("bad.json"), std::string::npos) << result.err;
    EXPECT_NE(result.err.find(bad.expectInError), std::string::npos) << result.err;
}

INSTANTIATE_TEST_SUITE_P(
    Errors, SluicePlayBadScene,
    ::testing::Values(
        BadScene{
            "unknownKey",
            R"({"simulation": {"spacng": 0.02}, "fluid": [{"box": {"min": [0,0,0], "max": [0.1,0.1,0.1]}}]})",
            "simulation.spacng"},
        BadScene{
            "wrongType",
            R"({"simulation": {"spacing": "fine"}, "fluid": [{"box": {"min": [0,0,0], "max": [0.1,0.1,0.1]}}]})",
            "simulation.spacing"},
        BadScene{
            "outOfRange",
            R"({"fluid": [{"box": {"min": [0,0,0], "max": [0.1,0.1,0.1]}}], "colliders": [{"asset": "{assets}/sphere.slc", "friction": 1.5}]})",
            "colliders[0].friction"},
        BadScene{
            "missingAsset",
            R"({"fluid": [{"box": {"min": [0,0,0], "max": [0.1,0.1,0.1]}}], "colliders": [{"asset": "nowhere.slc"}]})",
            "nowhere.slc"},
        BadScene{
            "corruptAsset",
            R"({"fluid": [{"box": {"min": [0,0,0], "max": [0.1,0.1,0.1]}}], "colliders": [{"asset": "garbage.slc"}]})",
            "garbage.slc"},
        BadScene{"syntax", R"({"fluid": [{"box": {"min": [0,0,0], "max": [0.1,0.1,0.1]}}],)",
                 "bad.json"},
        BadScene{"nothingToSimulate", R"({"simulation": {"spacing": 0.02}})", "fluid"},
        BadScene{
            "capacityTooSmall",
            R"({"simulation": {"capacity": 10}, "fluid": [{"box": {"min": [0,0,0], "max": [0.2,0.2,0.2]}}]})",
            "capacity"}),
    [](const auto& paramInfo) { return std::string(paramInfo.param.name); });

TEST(SluicePlay, MissingSceneFileAndBadArgumentsExitTwo) {
    const fs::path dir = tempDir("args");
    auto missing = play(dir, {(dir / "absent.json").string(), "--headless", "--steps", "1"});
    EXPECT_EQ(missing.code, 2) << shown(missing);
    EXPECT_NE(missing.err.find("absent.json"), std::string::npos) << missing.err;
    auto noSteps = play(dir, {(kAssets / "drop.json").string(), "--headless"});
    EXPECT_EQ(noSteps.code, 2) << shown(noSteps);
    auto badSteps = play(dir, {(kAssets / "drop.json").string(), "--headless", "--steps", "-3"});
    EXPECT_EQ(badSteps.code, 2) << shown(badSteps);
    auto badLanes = play(dir, {(kAssets / "drop.json").string(), "--headless", "--steps", "1",
                               "--neighbour-lanes", "3"});
    EXPECT_EQ(badLanes.code, 2) << shown(badLanes);
    EXPECT_NE(badLanes.err.find("--neighbour-lanes"), std::string::npos) << badLanes.err;
}

// --neighbour-lanes and --raster-spheres reach the solver and the renderer, and --bench says
// what it ran with.
TEST(SluicePlay, BenchReportsItsNeighbourLanesAndSphereDrawing) {
    const fs::path dir = tempDir("bench-lanes");
    const auto result =
        play(dir, {(kAssets / "drop.json").string(), "--bench", "--warmup", "0", "--steps", "1",
                   "--neighbour-lanes", "4", "--bench-frames", "1", "--size", "64x48",
                   "--raster-spheres", "--bench-json", (dir / "b.json").string()});
    ASSERT_EQ(result.code, 0) << shown(result);
    const auto bench = nlohmann::json::parse(testrun::readText(dir / "b.json"));
    EXPECT_EQ(bench["neighbourLanes"].get<std::uint32_t>(), 4u);
    EXPECT_FALSE(bench["computeSmallSpheres"].get<bool>());
    EXPECT_NE(result.out.find("4 invocations per particle"), std::string::npos) << result.out;
}

} // namespace
} // namespace sluice::rt
