// Running an untrusted parser in a child process, so its crash, abort or hang becomes an Error.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "sluice/bake/import/TriangleSoup.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

struct IsolationLimits {
    std::chrono::milliseconds timeout{std::chrono::minutes(10)}; ///< wall time before SIGKILL
    std::uint64_t maxAddressSpaceBytes = std::uint64_t(16) << 30; ///< child RLIMIT_AS; 0: none
};

/// What the child of runIsolated cost, as far as the parent can tell.
struct IsolationReport {
    double wallSeconds = 0.0; ///< [s] from the fork to the child's answer, measured by the child
    double cpuSeconds = 0.0;  ///< [s] the child's CPU time (wait4)
};

/// Runs `work` in a forked child and returns the soup (or Error) it produced, copied back
/// through a pipe. A child that dies by a signal (assimp's compiled-in asserts abort), exits
/// without an answer, or runs past the timeout gives Error{MeshImport} naming `what` (the file).
/// The child runs only `work` and then _exit()s: no atexit handlers, no flushing of the
/// parent's buffers. The address-space cap is skipped under AddressSanitizer, which reserves
/// terabytes of shadow memory. `meanwhile`, if set, runs in this process right after the fork,
/// while the child works (the timeout counts from the fork); `report`, if set, receives the
/// child's times.
Result<TriangleSoup> runIsolated(const std::string& what, const IsolationLimits& limits,
                                 const std::function<Result<TriangleSoup>()>& work,
                                 const std::function<void()>& meanwhile = {},
                                 IsolationReport* report = nullptr);

/// Stops the worker threads that libraries start (log4cplus's pool, loaded with OpenVDB; TBB's
/// workers, which the next parallel algorithm starts again), as runIsolated does before each
/// fork, and gives threads still exiting time to go. For embedders whose process forks
/// on its own (a Python process pool): called before forking, the children inherit no thread
/// that was holding a lock.
void prepareForFork();

} // namespace sluice::bake
