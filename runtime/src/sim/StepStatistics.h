// Private: the statistics' part of a Simulation's state: the GPU statistics buffer the passes
// add to, the commands queued, and the passes' timers.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/rt/sim/GpuCommandCount.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

struct StepStatistics {
    gpu::Buffer statsBuf;     // PbfStats, then PbfIterationStats per iteration (shared/Pbf.h)
    GpuCommandCount commands; // queued by the substeps and the step statistics, all steps
    std::vector<gpu::GpuTimer> timers;                               // per Pass
    std::array<std::uint64_t, std::size_t(Pass::Count)> drainedNs{}; // totals at the last drain
};

} // namespace sluice::rt
