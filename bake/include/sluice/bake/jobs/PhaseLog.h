// Wall and CPU time of the consecutive phases of one process, for `sluice-bake bake --profile`.
#pragma once

#include <chrono>
#include <string>
#include <string_view>
#include <vector>

namespace sluice::bake {

/// One phase of a PhaseLog.
struct Phase {
    std::string name;
    double wallSeconds = 0.0; ///< [s]
    /// [s] CPU time of the whole process (every thread: llvmpipe's, TBB's, workers') and of the
    /// child processes it waited for in the phase (the isolated import).
    double cpuSeconds = 0.0;
    /// Ran on another thread or in a child process beside the timeline (its wall time is inside other phases), so it
    /// is not part of their sum; its CPU time is already in theirs.
    bool overlapped = false;
};

/// [s] wall time from `start` to now (steady clock).
double secondsSince(std::chrono::steady_clock::time_point start);

/// [s] CPU time of this process (every thread) and of its waited-for children so far.
double processCpuSeconds();

/// [s] how long this process has existed: now minus the start time the kernel records for it
/// (/proc/self/stat, in clock ticks, so up to 10 ms more than the truth); -1 if unknown.
double processAgeSeconds();

/// A timeline of consecutive phases. The first phase is the time from the start of the process
/// (its kernel start time: loading the program and its libraries, static initialization, the
/// parsing of the arguments) to the log's construction; after that each lap() closes the phase
/// that ran since the previous lap under its name, so the phases follow each other without gaps
/// and their sum is the time from process start to the last lap. Work on another thread is
/// added with addOverlapped. One thread laps; not thread-safe.
class PhaseLog {
public:
    /// Starts the timeline now; `startupName` names the phase before it.
    explicit PhaseLog(std::string_view startupName = "start-up");

    /// Closes the running phase under `name`.
    void lap(std::string_view name);
    /// Records work that ran on another thread beside the timeline.
    void addOverlapped(std::string_view name, double wallSeconds, double cpuSeconds);

    /// Every phase in order, overlapped ones where they were added.
    const std::vector<Phase>& phases() const { return m_phases; }
    /// [s] the sum of the timeline's phases (not the overlapped ones).
    double sumSeconds() const;
    /// [s] the process's age at the last lap, measured independently of the phases
    /// (processAgeSeconds); the phases' sum when the age is unknown.
    double totalSeconds() const { return m_totalSeconds; }

private:
    std::vector<Phase> m_phases;
    std::chrono::steady_clock::time_point m_lapStart;
    double m_lapCpu = 0.0;
    double m_totalSeconds = 0.0;
};

/// log->lap(name) where there is a log: for code that laps only when asked to.
inline void lap(PhaseLog* log, std::string_view name) {
    if (log)
        log->lap(name);
}

} // namespace sluice::bake
