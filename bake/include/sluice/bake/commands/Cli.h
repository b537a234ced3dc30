// The sluice-bake command line (CLI11): bake, validate, info, export, gl-info, batch, surface.
#pragma once

#include "sluice/format/support/ExitCodes.h" // the exit codes runCli returns

namespace sluice::bake {

/// Runs sluice-bake with the given arguments and returns the process exit code
/// (sluice/format/ExitCodes.h). Never throws.
int runCli(int argc, char** argv);

} // namespace sluice::bake
