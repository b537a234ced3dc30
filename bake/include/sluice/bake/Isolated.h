// Running an untrusted parser in a child process, so its crash, abort or hang becomes an Error.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "sluice/bake/TriangleSoup.h"
#include "sluice/format/Result.h"

namespace sluice::bake {

struct IsolationLimits {
    std::chrono::milliseconds timeout{std::chrono::minutes(10)}; ///< wall time before SIGKILL
    std::uint64_t maxAddressSpaceBytes = std::uint64_t(16) << 30; ///< child RLIMIT_AS; 0: none
};

/// Runs `work` in a forked child and returns the soup (or Error) it produced, copied back
/// through a pipe. A child that dies by a signal (assimp's compiled-in asserts abort), exits
/// without an answer, or runs past the timeout gives Error{MeshImport} naming `what` (the file).
/// The child runs only `work` and then _exit()s: no atexit handlers, no flushing of the
/// parent's buffers. The address-space cap is skipped under AddressSanitizer, which reserves
/// terabytes of shadow memory.
Result<TriangleSoup> runIsolated(const std::string& what, const IsolationLimits& limits,
                                 const std::function<Result<TriangleSoup>()>& work);

/// Stops the worker threads that libraries load with (log4cplus, through OpenVDB), as
/// runIsolated does before its first fork. For embedders whose process forks on its own (a
/// Python process pool): called once early, the forked children inherit no half-copied pool.
void prepareForFork();

} // namespace sluice::bake
