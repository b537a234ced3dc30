// The files and folders a sluice-play run writes, checked and their folders created before any
// work starts, so a typo in a path costs a second, not a whole simulation.
#pragma once

#include <string>
#include <vector>

#include "sluice/format/support/Result.h"

namespace sluice::rt {

/// One output of a run, as the command line names it.
struct RunOutput {
    std::string option;  ///< "--stats-json"
    std::string path;    ///< as given; empty: not asked for (skipped)
    bool folder = false; ///< true: a folder the run writes into; false: a file
};

/// Checks every output first, then creates the folders they need: a file's parent folders, a
/// folder output and its parents. InvalidArgument naming the option and the path when a file
/// output is an existing folder, a folder output is an existing file, or a folder on the way
/// is a file; Io when a folder cannot be created or the nearest existing folder is not
/// writable. Nothing is created unless every output passes the checks.
Result<void> prepareRunOutputs(const std::vector<RunOutput>& outputs);

} // namespace sluice::rt
