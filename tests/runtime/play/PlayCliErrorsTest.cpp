// sluice-play's command-line and scene-file errors: exit 2 and one line naming the program,
// before any GL work.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ProgramRun.h"

namespace sluice::rt {
namespace {

namespace fs = std::filesystem;
using testrun::RunResult;
using testrun::shown;

/// Runs sluice-play with `args` in a fresh folder of its own under the build tree.
RunResult play(const std::vector<std::string>& args) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path dir = fs::path(SLUICE_TEST_TMP) / info->name();
    fs::create_directories(dir);
    return testrun::runProgram(SLUICE_PLAY_EXE, dir, args);
}

/// A parse error: exit 2, nothing on stdout, exactly `message` on stderr.
void expectParseError(const std::vector<std::string>& args, const std::string& message) {
    const RunResult run = play(args);
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_EQ(run.out, "") << shown(run);
    EXPECT_EQ(run.err, message + " (see sluice-play --help)\n") << shown(run);
}

TEST(PlayCliErrors, AMisspelledOptionSuggestsTheClosestOne) {
    expectParseError({"scene.json", "--stesp", "10"},
                     "sluice-play: unknown option '--stesp' (did you mean '--steps'?)");
    expectParseError({"scene.json", "--headles"},
                     "sluice-play: unknown option '--headles' (did you mean '--headless'?)");
    expectParseError({"scene.json", "--frobnicate"}, "sluice-play: unknown option '--frobnicate'");
}

TEST(PlayCliErrors, StepsMustBeAWholeNumberAtLeastOneAndTheLimitIsNotAdvertised) {
    expectParseError({"scene.json", "--steps", "0"},
                     "sluice-play: --steps 0: expected a whole number of steps >= 1");
    expectParseError({"scene.json", "--steps", "abc"}, "sluice-play: --steps abc: not a number");
    expectParseError({"scene.json", "--steps", "2.5"},
                     "sluice-play: --steps 2.5: not a whole number");
    expectParseError({"scene.json", "--steps", "1e15"},
                     "sluice-play: --steps 1e15: too many steps");
    const RunResult help = play({"--help"});
    EXPECT_EQ(help.code, 0) << shown(help);
    EXPECT_NE(help.out.find("--steps"), std::string::npos) << help.out;
    EXPECT_EQ(help.out.find("1099511627776"), std::string::npos) << help.out;
}

TEST(PlayCliErrors, NonNumbersAndOutOfRangeValuesAreSaidPlainly) {
    expectParseError({"scene.json", "--zoom", "1000"},
                     "sluice-play: --zoom 1000: expected a number from 0.01 to 100");
    expectParseError({"scene.json", "--fps", "-3"},
                     "sluice-play: --fps -3: expected a finite number > 0");
    expectParseError({"scene.json", "--steps-per-frame", "0"},
                     "sluice-play: --steps-per-frame 0: expected a whole number from 1 to 1000");
    // An option without a check of its own still says "not a number".
    expectParseError({"scene.json", "--warmup", "abc"}, "sluice-play: --warmup abc: not a number");
}

TEST(PlayCliErrors, AMissingSceneOrValueIsNamed) {
    expectParseError({"--headless"}, "sluice-play: missing scene");
    expectParseError({"scene.json", "--steps"}, "sluice-play: --steps needs a value");
}

/// A fresh folder `name` under this test's own, holding `json` as scene.json and a placeholder
/// ball.slc (the scene reader only checks that a collider's asset exists).
fs::path sceneFolder(const std::string& name, const std::string& json) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path dir = fs::path(SLUICE_TEST_TMP) / info->name() / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "scene.json", std::ios::binary) << json;
    std::ofstream(dir / "ball.slc", std::ios::binary) << "never read: the scene is rejected first";
    return dir;
}

/// The names in `dir`, sorted.
std::vector<std::string> namesIn(const fs::path& dir) {
    std::vector<std::string> names;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir))
        names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

TEST(PlayCliErrors, AHostileDynamicColliderExitsTwoNamingTheSceneAndPathAndWritesNothing) {
    struct Case {
        const char* name;
        const char* collider; // keys after "asset"
        const char* problem;  // the message after "<scene>: "
    };
    const Case cases[] = {
        {"zeroDensity", R"("dynamic": {"density": 0})",
         "colliders[0].dynamic.density: 0 is out of range: must be > 0 [InvalidArgument]"},
        {"negativeDensity", R"("dynamic": {"density": -5})",
         "colliders[0].dynamic.density: -5 is out of range: must be > 0 [InvalidArgument]"},
        {"hugeDensity", R"("dynamic": {"density": 1e39})",
         "colliders[0].dynamic.density: 1e+39 is not finite as a 32-bit float (largest "
         "3.4028235e+38) [NonFinite]"},
        {"withMotion", R"("dynamic": {"mass": 1}, "motion": {"linearVelocity": [1, 0, 0]})",
         "colliders[0].dynamic: not allowed with \"motion\": a collider is moved by the fluid "
         "(dynamic) or by its motion (kinematic), not both [BadMetadata]"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const fs::path dir = sceneFolder(
            c.name, std::string(R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
                                    "colliders": [{"asset": "ball.slc", )") +
                        c.collider + "}]}");
        const std::string scene = (dir / "scene.json").string();
        const RunResult run = testrun::runProgram(SLUICE_PLAY_EXE, dir,
                                                  {scene, "--headless", "--steps", "1",
                                                   "--stats-json", (dir / "out/s.json").string(),
                                                   "--dump-ply", (dir / "ply").string(), "--frames",
                                                   (dir / "png").string(), "--size", "64x36"});
        EXPECT_EQ(run.code, 2) << shown(run);
        EXPECT_EQ(run.out, "") << shown(run);
        EXPECT_EQ(run.err, "sluice-play: " + scene + ": " + c.problem + "\n") << shown(run);
        // Nothing but what the test wrote: no output file or folder was created.
        EXPECT_EQ(namesIn(dir),
                  (std::vector<std::string>{"ball.slc", "scene.json", "stderr.txt", "stdout.txt"}));

        // The window is refused the same way, before it looks for a display (which would be 3).
        const RunResult window = testrun::runProgram(
            "env", dir, {"-u", "DISPLAY", "-u", "WAYLAND_DISPLAY", SLUICE_PLAY_EXE, scene});
        EXPECT_EQ(window.code, 2) << shown(window);
        EXPECT_EQ(window.err, run.err) << shown(window);
    }
}

TEST(PlayCliErrors, HelpAndVersionStillExitZero) {
    const RunResult version = play({"--version"});
    EXPECT_EQ(version.code, 0) << shown(version);
    EXPECT_EQ(version.out.rfind("sluice-play ", 0), 0u) << version.out;
    EXPECT_EQ(version.err, "");
}

} // namespace
} // namespace sluice::rt
