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

/// Runs sluice-bake with `args`, capturing stdout and stderr in files in `dir`.
inline RunResult runBake(const std::filesystem::path& dir, const std::vector<std::string>& args) {
    return testrun::runProgram(SLUICE_BAKE_EXE, dir, args);
}

} // namespace sluice::bake::clirun
