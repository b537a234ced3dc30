// The sluice-play command line: loads a scene and its colliders and plays it.
#pragma once

#include "sluice/format/support/ExitCodes.h" // the exit codes runPlay returns
#include "sluice/format/support/Result.h"

namespace sluice::rt {

/// Prints "sluice-play: MESSAGE" on stderr and returns exitCodeFor(error).
int reportFailure(const Error& error);

/// Runs sluice-play with the given arguments; returns the process exit code
/// (sluice/format/ExitCodes.h). Never throws.
int runPlay(int argc, char** argv);

} // namespace sluice::rt
