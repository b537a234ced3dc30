// A thread-safe progress bar on stderr for long bakes and validations.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace sluice::bake {

/// Counts finished work items from any thread. Draws a bar on stderr once the work has run for
/// more than a second (redrawn in place on a terminal, a line per 10 % otherwise), and a final
/// line with items per second. Silent when `enabled` is false.
class Progress {
public:
    Progress(std::string label, std::uint64_t total, bool enabled = true);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Adds `n` finished items; cheap enough to call per row of voxels.
    void add(std::uint64_t n);
    /// Ends the bar (also done by the destructor) and returns items per second.
    double finish();

private:
    void draw(std::uint64_t done, bool final);

    std::string m_label;
    std::uint64_t m_total;
    bool m_enabled;
    bool m_tty;
    bool m_finished = false;
    bool m_drawn = false;
    int m_lastDecile = -1;
    std::atomic<std::uint64_t> m_done{0};
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_lastDraw;
    std::mutex m_mutex;
    double m_rate = 0.0;
};

} // namespace sluice::bake
