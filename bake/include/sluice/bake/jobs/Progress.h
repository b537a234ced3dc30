// A thread-safe progress bar on stderr for long bakes and validations.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

namespace sluice::bake {

/// What add() throws once a poll asked to stop. Not a std::exception, so the bakers' handlers
/// for library exceptions let it through to the caller that installed the poll.
struct ProgressCancelled {};

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

    /// Called by add() on whichever thread counted, after counting, with the items done so far
    /// and the total. Returning false cancels the work: that add() and every later one throw
    /// ProgressCancelled (embedders use it for Ctrl-C and their own progress displays).
    using Poll = std::function<bool(std::uint64_t done, std::uint64_t total)>;
    void setPoll(Poll poll);

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
    Poll m_poll;
    std::atomic<bool> m_cancelled{false};
};

} // namespace sluice::bake
