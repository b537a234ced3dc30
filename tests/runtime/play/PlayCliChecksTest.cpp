// sluice-play's checks before a run, end to end: scene warnings and --strict, options that do
// nothing, and output paths checked and their folders created before any step.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ProgramRun.h"
#include "output/BodiesCsv.h"
#include "render/RenderTestSupport.h"

namespace sluice::rt {
namespace {

namespace fs = std::filesystem;
using testrun::shown;

const fs::path kAssets = SLUICE_BUILD_ASSETS_DIR; // scenes and baked colliders, side by side

using testrun::tempDir;

// Through test::runPlay: runs that render (--frames) must see the GL driver preloaded under
// ASan, or LeakSanitizer reports Mesa's caches when the driver unloads (RenderTestSupport.h).
testrun::RunResult play(const fs::path& dir, const std::vector<std::string>& args) {
    return test::runPlay(dir, args);
}

/// Writes `json` as `name` in `dir`; "{assets}" becomes the build's assets folder.
fs::path writeScene(const fs::path& dir, const std::string& name, std::string json) {
    const std::string token = "{assets}";
    for (std::size_t at; (at = json.find(token)) != std::string::npos;)
        json.replace(at, token.size(), kAssets.string());
    const fs::path path = dir / name;
    std::ofstream(path, std::ios::binary) << json;
    return path;
}

// 64 particles in a 0.5 m domain: nothing to warn about, quick on llvmpipe.
constexpr const char* kSmallScene = R"({"simulation": {"spacing": 0.05},
    "fluid": [{"box": {"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}}],
    "domain": {"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}})";

// The small scene plus a ball of water at (5, 5, 5), far outside the domain.
constexpr const char* kBallOutside = R"({"simulation": {"spacing": 0.05},
    "fluid": [{"box": {"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}},
              {"sphere": {"center": [5, 5, 5], "radius": 0.1}}],
    "domain": {"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}})";

TEST(SluicePlayChecks, WarnsAboutABallOutsideTheDomainAndStillRuns) {
    const fs::path dir = tempDir("ball-outside");
    const fs::path scene = writeScene(dir, "ball.json", kBallOutside);
    const auto run = play(dir, {scene.string(), "--headless", "--steps", "1", "--quiet"});
    ASSERT_EQ(run.code, 0) << shown(run);
    EXPECT_NE(run.err.find("sluice-play: warning: " + scene.string() +
                           ": fluid[1]: 19 of 19 particles start outside the domain box"),
              std::string::npos)
        << run.err;
    EXPECT_NE(run.err.find("[outside-domain]\n"), std::string::npos) << run.err;
}

// "boundary": "bodies" names the boundary model that was removed: the scene plays with the one
// model there is, after a warning that says so (--strict makes it an error, below).
TEST(SluicePlayChecks, WarnsAboutTheRemovedBoundaryModelAndPlaysWithTheOneModel) {
    const fs::path dir = tempDir("removed-boundary");
    const fs::path scene = writeScene(dir, "old.json", R"({"simulation": {"spacing": 0.05,
        "boundary": "bodies"}, "fluid": [{"box": {"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}}],
        "domain": {"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}})");
    const auto run = play(dir, {scene.string(), "--headless", "--steps", "2", "--quiet"});
    ASSERT_EQ(run.code, 0) << shown(run);
    EXPECT_NE(run.err.find("sluice-play: warning: " + scene.string() +
                           ": simulation.boundary: \"bodies\" was removed; the walls, colliders "
                           "and bodies all add boundary volume now"),
              std::string::npos)
        << run.err;
    EXPECT_NE(run.err.find("[removed-boundary-model]\n"), std::string::npos) << run.err;
    // "solids", the one model's name, and no key at all say nothing.
    const fs::path named = writeScene(dir, "named.json", R"({"simulation": {"spacing": 0.05,
        "boundary": "solids"}, "fluid": [{"box": {"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}}],
        "domain": {"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}})");
    const auto quiet = play(dir, {named.string(), "--headless", "--steps", "1", "--quiet"});
    ASSERT_EQ(quiet.code, 0) << shown(quiet);
    EXPECT_EQ(quiet.err.find("warning"), std::string::npos) << quiet.err;
}

TEST(SluicePlayChecks, StrictStopsBeforeTheFirstStepAndWritesNothing) {
    const fs::path dir = tempDir("strict");
    const fs::path scene = writeScene(dir, "ball.json", kBallOutside);
    const auto run =
        play(dir, {scene.string(), "--headless", "--steps", "1", "--strict", "--stats-json",
                   (dir / "out/s.json").string(), "--dump-ply", (dir / "ply").string()});
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find("[outside-domain]"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("sluice-play: --strict turned the warning above into an error; "
                           "nothing was run"),
              std::string::npos)
        << run.err;
    EXPECT_EQ(run.out, ""); // no start-up line, no table
    EXPECT_FALSE(fs::exists(dir / "out"));
    EXPECT_FALSE(fs::exists(dir / "ply"));
}

// A mistake case names its test, and prints, by its name.
struct CaseName {
    template <typename Info> std::string operator()(const Info& info) const {
        return info.param.name;
    }
};

struct SceneMistake;
struct OptionMistake;
void PrintTo(const SceneMistake& mistake, std::ostream* out);
void PrintTo(const OptionMistake& mistake, std::ostream* out);

struct SceneMistake {
    const char* name;
    const char* json;
    const char* expectInError;
};

class SluicePlaySceneMistake : public ::testing::TestWithParam<SceneMistake> {};

TEST_P(SluicePlaySceneMistake, IsAnErrorWithStrict) {
    const SceneMistake& mistake = GetParam();
    const fs::path dir = tempDir(std::string("mistake-") + mistake.name);
    const fs::path scene = writeScene(dir, "scene.json", mistake.json);
    const auto run = play(dir, {scene.string(), "--headless", "--steps", "1", "--strict"});
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find(mistake.expectInError), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("--strict turned the"), std::string::npos) << run.err;
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, SluicePlaySceneMistake,
    ::testing::Values(
        SceneMistake{"fluidInCollider",
                     R"({"fluid": [{"box": {"min": [-0.2, -0.2, -0.2], "max": [0.2, 0.2, 0.2]}}],
                         "colliders": [{"asset": "{assets}/sphere.slc", "scale": 0.4}]})",
                     "scene.json: fluid[0]: "},
        SceneMistake{"emitterOutsideDomain",
                     R"({"emitters": [{"position": [0.2, 0.9, 0.2], "direction": [0, -1, 0],
                         "radius": 0.04, "speed": 1, "stop": 1}],
                         "domain": {"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}})",
                     "scene.json: emitters[0]: "},
        SceneMistake{"colliderInCentimetres",
                     R"({"fluid": [{"box": {"min": [60, 0, 0], "max": [60.1, 0.1, 0.1]}}],
                         "colliders": [{"asset": "{assets}/sphere.slc", "scale": 100}]})",
                     "`sluice-bake bake --scale 0.01`"},
        SceneMistake{"oddFixedIterations",
                     R"({"simulation": {"spacing": 0.05, "targetDensityError": 0,
                         "maxIterations": 3},
                         "fluid": [{"box": {"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}}]})",
                     "every substep runs 3 solver iterations, an odd count"},
        SceneMistake{"removedBoundaryModel",
                     R"({"simulation": {"spacing": 0.05, "boundary": "bodies"},
                         "fluid": [{"box": {"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}}]})",
                     "scene.json: simulation.boundary: \"bodies\" was removed"}),
    CaseName{});

struct OptionMistake {
    const char* name;
    std::vector<std::string> args; // after the scene
    const char* expectInError;
};

void PrintTo(const SceneMistake& mistake, std::ostream* out) {
    *out << mistake.name;
}
void PrintTo(const OptionMistake& mistake, std::ostream* out) {
    *out << mistake.name;
}

class SluicePlayOptionMistake : public ::testing::TestWithParam<OptionMistake> {};

TEST_P(SluicePlayOptionMistake, IsWarnedAndAnErrorWithStrict) {
    const OptionMistake& mistake = GetParam();
    const fs::path dir = tempDir(std::string("option-") + mistake.name);
    std::vector<std::string> args = {writeScene(dir, "small.json", kSmallScene).string()};
    args.insert(args.end(), mistake.args.begin(), mistake.args.end());
    args.push_back("--strict");
    const auto run = play(dir, args);
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find(std::string("sluice-play: warning: ") + mistake.expectInError),
              std::string::npos)
        << run.err;
    EXPECT_NE(run.err.find("nothing was run"), std::string::npos) << run.err;
}

INSTANTIATE_TEST_SUITE_P(
    Options, SluicePlayOptionMistake,
    ::testing::Values(
        OptionMistake{"maxFramesHeadless",
                      {"--headless", "--steps", "1", "--max-frames", "5"},
                      "--max-frames does nothing in a --headless run [unused-option]"},
        OptionMistake{"screenshotAfterEnd",
                      {"--headless", "--steps", "2", "--screenshot-at", "5"},
                      "--screenshot-at 5 is after the last step (--steps 2): no screenshot "
                      "would be written [screenshot-after-end]"},
        OptionMistake{"screenshotAfterMaxFrames",
                      {"--max-frames", "3", "--screenshot-at", "3"},
                      "--screenshot-at 3 is after the last step (--max-frames 3 shows steps up "
                      "to 2)"},
        OptionMistake{"statsJsonInWindow",
                      {"--stats-json", "s.json"},
                      "--stats-json does nothing in the window [unused-option]"},
        OptionMistake{"framesWithBench",
                      {"--bench", "--frames", "f"},
                      "--frames does nothing with --bench [unused-option]"},
        OptionMistake{"dumpEveryWithoutDumpPly",
                      {"--headless", "--steps", "1", "--dump-every", "2"},
                      "--dump-every does nothing without --dump-ply [unused-option]"},
        OptionMistake{"neighbourLanesInWindow",
                      {"--neighbour-lanes", "4"},
                      "--neighbour-lanes does nothing in the window [unused-option]"},
        OptionMistake{"surfaceEveryWithoutSurfaceMesh",
                      {"--headless", "--steps", "1", "--surface-every", "2"},
                      "--surface-every does nothing without --surface-mesh [unused-option]"},
        OptionMistake{"surfaceNormalisedWithoutSurfaceMesh",
                      {"--headless", "--steps", "1", "--surface-normalised"},
                      "--surface-normalised does nothing without --surface-mesh or --surface "
                      "mesh [unused-option]"},
        OptionMistake{"noSurfaceNormalisedWithoutSurfaceMesh",
                      {"--headless", "--steps", "1", "--no-surface-normalised"},
                      "--surface-normalised does nothing without --surface-mesh or --surface "
                      "mesh [unused-option]"},
        OptionMistake{"surfaceKernelWithoutSurfaceMesh",
                      {"--headless", "--steps", "1", "--surface-kernel", "poly6"},
                      "--surface-kernel does nothing without --surface-mesh or --surface mesh "
                      "[unused-option]"},
        OptionMistake{"surfaceIsoWithBench",
                      {"--bench", "--surface-iso", "0.4"},
                      "--surface-iso does nothing with --bench without --bench-frames and "
                      "--surface mesh [unused-option]"},
        OptionMistake{"surfaceAnisotropicWithoutSurfaceMesh",
                      {"--headless", "--steps", "1", "--surface-anisotropic"},
                      "--surface-anisotropic does nothing without --surface-mesh or --surface "
                      "mesh [unused-option]"},
        OptionMistake{"bodiesCsvWithoutBodies",
                      {"--headless", "--steps", "1", "--bodies-csv", "b.csv"},
                      "--bodies-csv does nothing for a scene without dynamic bodies"},
        OptionMistake{"rasterSpheresWithoutPictures",
                      {"--headless", "--steps", "1", "--raster-spheres"},
                      "--raster-spheres does nothing in a --headless run without --frames"}),
    CaseName{});

TEST(SluicePlayChecks, ShippedSceneStartsWithoutWarningsAndPrintsColliderSizes) {
    const fs::path dir = tempDir("shipped-strict");
    const auto run =
        play(dir, {(kAssets / "drop.json").string(), "--headless", "--steps", "1", "--strict"});
    ASSERT_EQ(run.code, 0) << shown(run);
    EXPECT_EQ(run.err, "");
    EXPECT_NE(run.out.find("  colliders[0] tank.slc: 0.8"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find(" m (scale 1)\n"), std::string::npos) << run.out;
}

TEST(SluicePlayChecks, CreatesMissingOutputFoldersBeforeTheRun) {
    const fs::path dir = tempDir("create-outputs");
    const fs::path scene = writeScene(dir, "small.json", kSmallScene);
    const auto run =
        play(dir, {scene.string(), "--headless", "--steps", "1", "--quiet", "--stats-json",
                   (dir / "a/b/s.json").string(), "--dump-ply", (dir / "c/ply").string(),
                   "--frames", (dir / "d/png").string(), "--size", "64x36"});
    ASSERT_EQ(run.code, 0) << shown(run);
    EXPECT_TRUE(fs::is_regular_file(dir / "a/b/s.json"));
    EXPECT_TRUE(fs::is_regular_file(dir / "c/ply/frame_000001.ply"));
    EXPECT_TRUE(fs::is_regular_file(dir / "d/png/frame_000001.png"));
}

TEST(SluicePlayChecks, AnOutputThatIsAFolderFailsBeforeTheRunAndNothingIsWritten) {
    const fs::path dir = tempDir("output-is-folder");
    const fs::path scene = writeScene(dir, "small.json", kSmallScene);
    fs::create_directories(dir / "taken");
    const auto run = play(dir, {scene.string(), "--headless", "--steps", "1", "--dump-ply",
                                (dir / "ply").string(), "--stats-json", (dir / "taken").string()});
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find("--stats-json " + (dir / "taken").string() + ": is a folder"),
              std::string::npos)
        << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_FALSE(fs::exists(dir / "ply"));
}

TEST(SluicePlayChecks, ABadSizeFailsBeforeAnyFolderIsCreated) {
    const fs::path dir = tempDir("bad-size");
    const fs::path scene = writeScene(dir, "small.json", kSmallScene);
    const auto run = play(dir, {scene.string(), "--headless", "--steps", "1", "--frames",
                                (dir / "png").string(), "--size", "0x10"});
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find("--size 0x10"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(dir / "png"));
}

TEST(SluicePlayChecks, BenchJsonGoesIntoAFolderCreatedFirst) {
    const fs::path dir = tempDir("bench-json-folder");
    const fs::path scene = writeScene(dir, "small.json", kSmallScene);
    const auto run = play(dir, {scene.string(), "--bench", "--warmup", "0", "--steps", "1",
                                "--bench-json", (dir / "results/b.json").string()});
    ASSERT_EQ(run.code, 0) << shown(run);
    EXPECT_TRUE(fs::is_regular_file(dir / "results/b.json"));
    fs::create_directories(dir / "taken");
    const auto taken = play(dir, {scene.string(), "--bench", "--warmup", "0", "--steps", "1",
                                  "--bench-json", (dir / "taken").string()});
    EXPECT_EQ(taken.code, 2) << shown(taken);
    EXPECT_EQ(taken.out, ""); // stopped before the benchmark
}

TEST(SluicePlayChecks, WindowOutputsAreCheckedBeforeTheWindowOpens) {
    const fs::path dir = tempDir("window-outputs");
    const fs::path scene = writeScene(dir, "small.json", kSmallScene);
    std::ofstream(dir / "frames") << "a file";
    // Without a display the window would exit 3; the path is refused first.
    const std::string command =
        "env -u DISPLAY -u WAYLAND_DISPLAY " + testrun::quote(SLUICE_PLAY_EXE) + " " +
        testrun::quote(scene.string()) + " --frames " + testrun::quote((dir / "frames").string()) +
        " 2>" + testrun::quote((dir / "err.txt").string());
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2);
    const std::string err = testrun::readText(dir / "err.txt");
    EXPECT_NE(err.find("--frames " + (dir / "frames").string() + ": is a file; give a folder"),
              std::string::npos)
        << err;
}

/// --bodies-csv against the statistics of the same run: the header, a row per body at step 0
/// and at each recorded step, and at each recorded step the same figures as "bodies".
void expectCsvMatchesStatistics(const std::string& csv, const nlohmann::json& stats) {
    std::istringstream in(csv);
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line + "\n", bodiesCsvHeader());
    std::vector<std::vector<std::string>> rows;
    while (std::getline(in, line)) {
        std::vector<std::string> fields;
        std::istringstream cells(line);
        for (std::string cell; std::getline(cells, cell, ',');)
            fields.push_back(cell);
        ASSERT_EQ(fields.size(), 25u) << line;
        rows.push_back(std::move(fields));
    }
    const auto& steps = stats["steps"];
    ASSERT_EQ(rows.size(), 4 * (steps.size() + 1)) << csv;
    EXPECT_EQ(rows[0][0], "0");
    for (std::size_t s = 0; s < steps.size(); ++s)
        for (std::size_t b = 0; b < 4; ++b) {
            const auto& row = rows[4 * (s + 1) + b];
            const auto& body = steps[s]["bodies"][b];
            EXPECT_EQ(std::stoull(row[0]), steps[s]["step"].get<std::uint64_t>());
            EXPECT_EQ(std::stoul(row[2]), b);
            EXPECT_EQ(std::stoul(row[3]), body["collider"].get<std::uint32_t>());
            for (int axis = 0; axis < 3; ++axis) {
                EXPECT_NEAR(std::stod(row[5 + axis]), body["origin"][axis].get<double>(), 1e-6);
                EXPECT_NEAR(std::stod(row[8 + axis]), body["centreOfMass"][axis].get<double>(),
                            1e-6);
                EXPECT_NEAR(std::stod(row[15 + axis]), body["linearVelocity"][axis].get<double>(),
                            1e-6);
                EXPECT_NEAR(std::stod(row[22 + axis]), body["force"][axis].get<double>(), 1e-5);
            }
            EXPECT_NEAR(std::stod(row[21]), body["submergedShare"].get<double>(), 1e-7);
        }
}

// A scene with dynamic bodies: the start-up lines name them, every statistics row has each
// body's state, each PLY frame has a body-transforms file whose matrix places the body's asset
// frame at its origin, and --bodies-csv has a row per recorded step and body with the same
// figures under the same names. (Here, through play(): the bodies' shaders fill Mesa caches
// that LeakSanitizer would report without the driver preloaded.)
TEST(SluicePlayBodies, WritesEachBodysStateAndTransformsBesideThePlyFrames) {
    const fs::path dir = tempDir("bodies");
    const auto result =
        play(dir, {(kAssets / "float.json").string(), "--headless", "--steps", "4", "--stats-every",
                   "2", "--deterministic", "--stats-json", (dir / "stats.json").string(),
                   "--dump-ply", (dir / "ply").string(), "--dump-every", "2", "--bodies-csv",
                   (dir / "bodies.csv").string()});
    ASSERT_EQ(result.code, 0) << shown(result);
    EXPECT_NE(result.out.find("body: collider 1, 0.432 kg, 1.728 L"), std::string::npos)
        << result.out;
    const auto stats = nlohmann::json::parse(testrun::readText(dir / "stats.json"));
    ASSERT_EQ(stats["steps"].size(), 2u);
    const auto& bodies = stats["steps"][1]["bodies"];
    ASSERT_EQ(bodies.size(), 4u); // three crates and the ball
    EXPECT_EQ(bodies[0]["collider"].get<int>(), 1);
    EXPECT_NEAR(bodies[0]["mass"].get<double>(), 250 * 0.12 * 0.12 * 0.12, 1e-6);
    EXPECT_LT(bodies[3]["linearVelocity"][1].get<double>(), -0.1) << "the ball is falling";
    for (const int step : {0, 2, 4}) {
        char name[40];
        std::snprintf(name, sizeof name, "frame_%06d.bodies.json", step);
        ASSERT_TRUE(fs::exists(dir / "ply" / name)) << name;
    }
    const auto frame =
        nlohmann::json::parse(testrun::readText(dir / "ply" / "frame_000004.bodies.json"));
    EXPECT_EQ(frame["step"].get<int>(), 4);
    ASSERT_EQ(frame["bodies"].size(), 4u);
    const auto& crate = frame["bodies"][0];
    EXPECT_EQ(crate["asset"].get<std::string>(), "crate.slc");
    // The same names for the same things: origin and centre of mass in both files (the crate
    // mesh's centre of mass is its origin), and the matrix's translation column is the origin.
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(crate["matrix"][axis][3].get<double>(), crate["origin"][axis].get<double>(),
                    1e-6);
        EXPECT_NEAR(crate["origin"][axis].get<double>(), bodies[0]["origin"][axis].get<double>(),
                    1e-6);
        EXPECT_NEAR(crate["centreOfMass"][axis].get<double>(),
                    bodies[0]["centreOfMass"][axis].get<double>(), 1e-6);
        EXPECT_NEAR(bodies[0]["origin"][axis].get<double>(),
                    bodies[0]["centreOfMass"][axis].get<double>(), 1e-5);
    }
    for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(crate["orientation"][c].get<double>(),
                    bodies[0]["orientation"][c].get<double>(), 1e-6);
    EXPECT_EQ(crate["matrix"][3], nlohmann::json::parse("[0.0, 0.0, 0.0, 1.0]"));
    expectCsvMatchesStatistics(testrun::readText(dir / "bodies.csv"), stats);
}

} // namespace
} // namespace sluice::rt
