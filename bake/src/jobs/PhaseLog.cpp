// The phase timeline of one process: steady-clock laps, process CPU time, the kernel's start time.
#include "sluice/bake/jobs/PhaseLog.h"

#include <ctime>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <sys/resource.h>
#include <unistd.h>

namespace sluice::bake {
namespace {

double seconds(const timeval& t) {
    return double(t.tv_sec) + 1e-6 * double(t.tv_usec);
}

/// [s] since boot when this process started (field 22 of /proc/self/stat, after the command
/// name, which may hold spaces and parentheses); -1 if unknown.
double processStartSinceBoot() {
    std::ifstream in("/proc/self/stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t close = text.rfind(')');
    if (close == std::string::npos)
        return -1.0;
    std::istringstream fields(text.substr(close + 2));
    std::string field;
    // Fields from 3 (state) on; the start time is field 22.
    for (int index = 3; index <= 22; ++index)
        if (!(fields >> field))
            return -1.0;
    const long ticks = ::sysconf(_SC_CLK_TCK);
    if (ticks <= 0)
        return -1.0;
    return double(std::stoull(field)) / double(ticks);
}

} // namespace

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double processCpuSeconds() {
    rusage self{}, children{};
    ::getrusage(RUSAGE_SELF, &self);
    ::getrusage(RUSAGE_CHILDREN, &children);
    return seconds(self.ru_utime) + seconds(self.ru_stime) + seconds(children.ru_utime) +
           seconds(children.ru_stime);
}

double processAgeSeconds() {
    const double start = processStartSinceBoot();
    timespec now{};
    // The kernel's start time counts from boot, suspend included: CLOCK_BOOTTIME.
    if (start < 0.0 || ::clock_gettime(CLOCK_BOOTTIME, &now) != 0)
        return -1.0;
    return double(now.tv_sec) + 1e-9 * double(now.tv_nsec) - start;
}

PhaseLog::PhaseLog(std::string_view startupName)
    : m_lapStart(std::chrono::steady_clock::now()), m_lapCpu(processCpuSeconds()) {
    const double age = processAgeSeconds();
    m_phases.push_back({std::string(startupName), age > 0.0 ? age : 0.0, m_lapCpu, false});
    m_totalSeconds = m_phases.back().wallSeconds;
}

void PhaseLog::lap(std::string_view name) {
    const auto now = std::chrono::steady_clock::now();
    const double cpu = processCpuSeconds();
    m_phases.push_back({std::string(name), std::chrono::duration<double>(now - m_lapStart).count(),
                        cpu - m_lapCpu, false});
    m_lapStart = now;
    m_lapCpu = cpu;
    const double age = processAgeSeconds();
    m_totalSeconds = age > 0.0 ? age : sumSeconds();
}

void PhaseLog::addOverlapped(std::string_view name, double wallSeconds, double cpuSeconds) {
    m_phases.push_back({std::string(name), wallSeconds, cpuSeconds, true});
}

double PhaseLog::sumSeconds() const {
    double sum = 0.0;
    for (const Phase& phase : m_phases)
        if (!phase.overlapped)
            sum += phase.wallSeconds;
    return sum;
}

} // namespace sluice::bake
