// Runs the sluice-bake program (SLUICE_BAKE_EXE) from tests: the shared program runner, with
// sluice-bake's path filled in.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ProgramRun.h"
#include "sluice/format/support/ExitCodes.h"

namespace sluice::bake::clirun {

using testrun::quote;
using testrun::readText;
using testrun::RunResult;
using testrun::shown;

/// The demo sphere the command-line tests bake (radius 0.25, 1280 triangles).
inline const std::filesystem::path kSphereObj =
    std::filesystem::path(SLUICE_SOURCE_DIR) / "assets" / "sphere.obj";

/// Runs sluice-bake with `args`, capturing stdout and stderr in files in `dir`.
inline RunResult runBake(const std::filesystem::path& dir, const std::vector<std::string>& args) {
    return testrun::runProgram(SLUICE_BAKE_EXE, dir, args);
}

/// A bad-input run: exit 2, the file named on stderr, OUT never created or changed.
inline void expectRejected(const std::filesystem::path& dir, const std::vector<std::string>& args,
                           const std::string& named, const std::filesystem::path& output) {
    const bool existed = std::filesystem::exists(output);
    const std::string before = existed ? readText(output) : std::string();
    const RunResult run = runBake(dir, args);
    EXPECT_EQ(run.code, kExitBadInput) << shown(run);
    EXPECT_NE(run.err.find(named), std::string::npos) << "stderr does not name " << named << "\n"
                                                      << run.err;
    EXPECT_EQ(std::filesystem::exists(output), existed);
    if (existed) {
        EXPECT_TRUE(readText(output) == before) << output << " changed";
    }
    // Nothing else (no temporary file) is left beside the output either.
    if (std::filesystem::is_directory(output.parent_path())) {
        for (const std::filesystem::directory_entry& entry :
             std::filesystem::directory_iterator(output.parent_path()))
            EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos)
                << entry.path();
    }
}

} // namespace sluice::bake::clirun
