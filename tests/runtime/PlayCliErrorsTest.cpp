// sluice-play's command-line errors: exit 2 and one line naming the program, before any GL work.
#include <filesystem>
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

TEST(PlayCliErrors, HelpAndVersionStillExitZero) {
    const RunResult version = play({"--version"});
    EXPECT_EQ(version.code, 0) << shown(version);
    EXPECT_EQ(version.out.rfind("sluice-play ", 0), 0u) << version.out;
    EXPECT_EQ(version.err, "");
}

} // namespace
} // namespace sluice::rt
