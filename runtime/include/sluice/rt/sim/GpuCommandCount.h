// What a piece of GPU work queued, counted where each command is issued: --bench reports it
// per substep, because on a GPU a small scene's substep costs about its dispatches and barriers
// times their latency (docs/performance.md, "Dispatches and barriers").
#pragma once

#include <cstdint>

namespace sluice::rt {

struct GpuCommandCount {
    std::uint64_t dispatches = 0; ///< compute dispatches, the indirect ones included
    std::uint64_t indirect = 0;   ///< of them, indirect ones (the solver's; idle after a stop)
    std::uint64_t barriers = 0;   ///< glMemoryBarrier calls

    GpuCommandCount& operator+=(const GpuCommandCount& o) {
        dispatches += o.dispatches;
        indirect += o.indirect;
        barriers += o.barriers;
        return *this;
    }
    friend GpuCommandCount operator-(GpuCommandCount a, const GpuCommandCount& b) {
        a.dispatches -= b.dispatches;
        a.indirect -= b.indirect;
        a.barriers -= b.barriers;
        return a;
    }
};

} // namespace sluice::rt
