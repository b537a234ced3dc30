// Runs the sluice-bake program (SLUICE_BAKE_EXE) from tests: the shared program runner, with
// sluice-bake's path filled in.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "ProgramRun.h"

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

} // namespace sluice::bake::clirun
