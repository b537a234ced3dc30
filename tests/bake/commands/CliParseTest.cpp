// sluice-bake's command line: misspelled commands and options, numbers and missing arguments,
// each an exit 2 with one plain message and nothing written.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "CliRun.h"
#include "TestMeshes.h"
#include "sluice/bake/commands/Cli.h"

namespace sluice::bake {
namespace {

namespace fs = std::filesystem;
using namespace clirun;

/// A parse error of sluice-bake: exit 2, nothing on stdout, exactly `message` and the help hint
/// on stderr.
void expectParseError(const std::vector<std::string>& args, const std::string& message,
                      const std::string& command = "sluice-bake") {
    // A folder per test: ctest runs the tests of this file side by side.
    const fs::path dir =
        testmesh::tempDir(std::string("cli-parse-errors-") +
                          ::testing::UnitTest::GetInstance()->current_test_info()->name());
    const RunResult run = runBake(dir, args);
    EXPECT_EQ(run.code, kExitBadInput) << shown(run);
    EXPECT_EQ(run.out, "") << shown(run);
    EXPECT_EQ(run.err, message + " (see " + command + " --help)\n") << shown(run);
    EXPECT_FALSE(fs::exists(dir / "x.slc"));
}

TEST(Cli, AMisspelledCommandSuggestsTheClosestOne) {
    expectParseError({"bkae", "x.obj"},
                     "sluice-bake: unknown command 'bkae' (did you mean 'bake'?)");
    expectParseError({"frob"}, "sluice-bake: unknown command 'frob'");
    expectParseError({}, "sluice-bake: missing a command (one of: bake, validate, info, export, "
                         "gl-info, batch, surface)");
    expectParseError({"--no-such-flag"}, "sluice-bake: unknown option '--no-such-flag'");
}

TEST(Cli, AMisspelledOptionSuggestsTheClosestOptionOfItsCommand) {
    const std::string bake = "sluice-bake bake";
    expectParseError({"bake", "x.obj", "-o", "x.slc", "--resolutoin", "16"},
                     "sluice-bake bake: unknown option '--resolutoin' (did you mean "
                     "'--resolution'?)",
                     bake);
    expectParseError({"bake", "--voxel-sise=0.1", "x.obj", "-o", "x.slc"},
                     "sluice-bake bake: unknown option '--voxel-sise' (did you mean "
                     "'--voxel-size'?)",
                     bake);
    expectParseError({"batch", "m.json", "--jbos", "2"},
                     "sluice-bake batch: unknown option '--jbos' (did you mean '--jobs'?)",
                     "sluice-bake batch");
    expectParseError({"bake", "x.obj", "-o", "x.slc", "extra"},
                     "sluice-bake bake: unexpected argument 'extra'", bake);
}

TEST(Cli, NumbersAreCheckedAndTheProblemSaidPlainly) {
    const std::string bake = "sluice-bake bake";
    expectParseError({"bake", "x.obj", "-o", "x.slc", "--resolution", "abc"},
                     "sluice-bake bake: --resolution abc: not a number", bake);
    expectParseError({"bake", "x.obj", "-o", "x.slc", "--resolution", "0"},
                     "sluice-bake bake: --resolution 0: expected a whole number from 1 to 4096",
                     bake);
    expectParseError({"bake", "x.obj", "-o", "x.slc", "--resolution", "8.5"},
                     "sluice-bake bake: --resolution 8.5: not a whole number", bake);
    expectParseError({"bake", "x.obj", "-o", "x.slc", "--scale", "nan"},
                     "sluice-bake bake: --scale nan: expected a finite number > 0", bake);
    expectParseError({"bake", "x.obj", "-o", "x.slc", "--padding", "wide"},
                     "sluice-bake bake: --padding wide: not a number", bake);
    expectParseError({"batch", "m.json", "--jobs", "0"},
                     "sluice-bake batch: --jobs 0: expected a whole number from 1 to 256",
                     "sluice-bake batch");
    expectParseError({"validate", "a.slc", "a.obj", "--seed", "xyz"},
                     "sluice-bake validate: --seed xyz: not a number", "sluice-bake validate");
}

TEST(Cli, AMissingArgumentIsNamed) {
    expectParseError({"bake", "x.obj"}, "sluice-bake bake: missing --output", "sluice-bake bake");
    expectParseError({"bake", "-o", "x.slc"}, "sluice-bake bake: missing MESH", "sluice-bake bake");
    expectParseError({"info"}, "sluice-bake info: missing ASSET", "sluice-bake info");
    expectParseError({"bake", "x.obj", "-o", "x.slc", "--resolution"},
                     "sluice-bake bake: --resolution needs a value", "sluice-bake bake");
}

} // namespace
} // namespace sluice::bake
