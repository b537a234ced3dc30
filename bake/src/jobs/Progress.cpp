// A thread-safe progress bar on stderr for long bakes and validations.
#include "sluice/bake/jobs/Progress.h"

#include <cstdio>
#include <utility>

#include <unistd.h>

#include "sluice/bake/jobs/PhaseLog.h"

namespace sluice::bake {

namespace {
using Clock = std::chrono::steady_clock;
constexpr auto kQuietPeriod = std::chrono::seconds(1);         // draw nothing before this
constexpr auto kRedrawPeriod = std::chrono::milliseconds(100); // terminal redraw rate
constexpr int kBarWidth = 30;
} // namespace

Progress::Progress(std::string label, std::uint64_t total, bool enabled)
    : m_label(std::move(label)), m_total(total), m_enabled(enabled),
      m_tty(isatty(fileno(stderr)) != 0), m_start(Clock::now()), m_lastDraw(m_start) {}

Progress::~Progress() {
    finish();
}

void Progress::setPoll(Poll poll) {
    m_poll = std::move(poll);
}

void Progress::add(std::uint64_t n) {
    const std::uint64_t done = m_done.fetch_add(n, std::memory_order_relaxed) + n;
    if (m_poll) {
        if (m_cancelled.load(std::memory_order_relaxed) || !m_poll(done, m_total)) {
            m_cancelled.store(true, std::memory_order_relaxed);
            throw ProgressCancelled{};
        }
    }
    if (!m_enabled)
        return;
    const Clock::time_point now = Clock::now();
    if (now - m_start < kQuietPeriod)
        return;
    // Whoever holds the lock draws; everyone else just counts and moves on.
    std::unique_lock lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock() || m_finished)
        return;
    if (m_tty) {
        if (m_drawn && now - m_lastDraw < kRedrawPeriod)
            return;
    } else {
        const int decile = m_total ? int(std::min<std::uint64_t>(done * 10 / m_total, 10)) : 10;
        if (decile <= m_lastDecile)
            return;
        m_lastDecile = decile;
    }
    m_lastDraw = now;
    draw(done, false);
}

double Progress::finish() {
    std::lock_guard lock(m_mutex);
    if (m_finished)
        return m_rate;
    m_finished = true;
    const double seconds = secondsSince(m_start);
    const std::uint64_t done = m_done.load();
    m_rate = seconds > 0.0 ? double(done) / seconds : 0.0;
    // Short work stays silent; anything that ran past the quiet period ends with its rate.
    if (m_enabled && (m_drawn || seconds >= 1.0))
        draw(done, true);
    return m_rate;
}

void Progress::draw(std::uint64_t done, bool final) {
    const double fraction = m_total ? std::min(1.0, double(done) / double(m_total)) : 1.0;
    const double seconds = secondsSince(m_start);
    if (final) {
        // "\r\033[K" returns to the start of the bar and clears it on a terminal.
        std::fprintf(stderr, "%s%s: %llu voxels in %.2f s, %.3g voxels/s\n",
                     m_tty && m_drawn ? "\r\033[K" : "", m_label.c_str(),
                     static_cast<unsigned long long>(done), seconds, m_rate);
    } else if (m_tty) {
        const int filled = int(fraction * kBarWidth);
        char bar[kBarWidth + 1];
        for (int i = 0; i < kBarWidth; ++i)
            bar[i] = i < filled ? '#' : '.';
        bar[kBarWidth] = '\0';
        std::fprintf(stderr, "\r%s [%s] %5.1f %%  %.1f s", m_label.c_str(), bar, fraction * 100.0,
                     seconds);
    } else {
        std::fprintf(stderr, "%s: %3.0f %% (%.1f s)\n", m_label.c_str(), fraction * 100.0, seconds);
    }
    std::fflush(stderr);
    m_drawn = true;
}

} // namespace sluice::bake
