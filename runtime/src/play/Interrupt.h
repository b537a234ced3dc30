// Ctrl-C and `kill`: sluice-play ends a run after the current step and writes what it was
// asked for, as far as it got, instead of dying with its outputs half done.
#pragma once

#include <signal.h>

namespace sluice::rt {

/// While alive, SIGINT and SIGTERM only set a flag (`requested()`), which the run loops read
/// between steps. The first signal also restores the default action, so a second Ctrl-C ends
/// the process at once (the user who does not want to wait). The previous handlers come back
/// when the guard goes. One guard at a time.
class InterruptGuard {
public:
    InterruptGuard();
    ~InterruptGuard();
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    /// The signal received (SIGINT or SIGTERM), 0 when none was.
    static int requested();

    /// The exit code a run stopped by `requested()` ends with: 128 + the signal (130 for
    /// SIGINT, 143 for SIGTERM), as a shell reports a process the signal killed.
    static int exitCode();

    /// "SIGINT" or "SIGTERM".
    static const char* signalName();

private:
    struct sigaction m_savedInterrupt {}; ///< the handlers before the guard
    struct sigaction m_savedTerminate {};
};

} // namespace sluice::rt
