// GPU time of a pass with GL timestamp queries, read back without stalling the pipeline.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "sluice/gpu/Gl.h"

namespace sluice::gpu {

/// Times the GL commands between begin() and end() on the GPU, once per frame or pass.
///
/// Each measurement is a pair of GL_TIMESTAMP queries (glQueryCounter) rather than one
/// GL_TIME_ELAPSED query: timestamp pairs may nest and overlap (a frame timer around pass
/// timers), and llvmpipe's GL_TIME_ELAPSED misses compute dispatches while its timestamps
/// do not. Results arrive a few frames late: each begin()/end() pair uses the next slot of a
/// ring, and poll() collects the ones the GPU has finished without waiting. Only if all
/// `ringSize` slots are still in flight does begin() wait for the oldest.
/// RAII, move-only; needs its context current.
class GpuTimer {
public:
    /// Creates `ringSize` slots of two queries (>= 1; 4 covers the usual 2-3 frames of latency).
    explicit GpuTimer(std::size_t ringSize = 4);
    GpuTimer(GpuTimer&& other) noexcept;
    GpuTimer& operator=(GpuTimer&& other) noexcept;
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;
    ~GpuTimer();

    /// Starts timing. Precondition: not already begun.
    void begin();
    /// Stops timing. Precondition: begun.
    void end();

    /// Collects finished measurements without blocking; returns the newest one collected by
    /// this call [ns], or nothing if none finished since the last call.
    std::optional<std::uint64_t> poll();
    /// Waits for every measurement in flight and returns the newest [ns], for tests and
    /// benchmarks. Precondition: at least one begin()/end() pair since construction.
    std::uint64_t elapsedNs();

    /// Newest collected measurement [ns], if any.
    std::optional<std::uint64_t> latestNs() const { return m_latest; }
    /// Measurements ended but not yet collected.
    std::size_t pending() const { return m_pending; }
    /// Measurements collected so far, and their sum [ns] (for averages).
    std::uint64_t completed() const { return m_completed; }
    std::uint64_t totalNs() const { return m_totalNs; }

    /// begin() on construction, end() on destruction.
    class Scope {
    public:
        explicit Scope(GpuTimer& timer) : m_timer(timer) { m_timer.begin(); }
        ~Scope() { m_timer.end(); }
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;

    private:
        GpuTimer& m_timer;
    };

private:
    /// Reads the oldest pending query; `wait` blocks until it is available.
    bool collectOldest(bool wait);
    void release();

    std::vector<GLuint> m_queries; // slot i: start 2i, end 2i + 1
    std::size_t m_next = 0;        // ring index of the next begin()
    std::size_t m_pending = 0;     // ended, not yet collected; the oldest is m_next - m_pending
    bool m_active = false;
    std::optional<std::uint64_t> m_latest;
    std::uint64_t m_completed = 0;
    std::uint64_t m_totalNs = 0;
};

} // namespace sluice::gpu
