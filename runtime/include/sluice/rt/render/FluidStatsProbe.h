// Live statistics for a viewer without a stall: mean and max density error and max speed of the
// particles, reduced on the GPU and read back a few frames later.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"

namespace sluice::rt {

class Simulation;

/// One measurement of the particles after a step.
struct FluidStats {
    std::uint64_t step = 0; ///< sim.steps() when it was recorded
    std::uint32_t particles = 0;
    double avgDensityError = 0.0; ///< mean C_i = max(rho / rho0 - 1, 0), last lambda pass
    double maxDensityError = 0.0;
    double maxSpeed = 0.0; ///< [m/s]
};

/// A ring of small reduction buffers, each copied into a mapped buffer behind a fence.
/// Needs its context current, destruction included. Move-only.
class FluidStatsProbe {
public:
    /// `slots` measurements may be in flight (>= 1). Errors from compiling the reduction.
    static Result<FluidStatsProbe> create(std::size_t slots = 4);

    FluidStatsProbe(FluidStatsProbe&&) noexcept;
    FluidStatsProbe& operator=(FluidStatsProbe&&) noexcept;
    ~FluidStatsProbe();

    /// Queues a reduction over the simulation's current velocities. Returns false, and queues
    /// nothing, while every slot is still in flight (it never waits).
    bool record(const Simulation& sim);

    /// The newest measurement that finished since the last call; never waits unless `wait`,
    /// which waits for every measurement in flight.
    std::optional<FluidStats> poll(bool wait = false);

private:
    struct Slot;
    FluidStatsProbe();

    gpu::Program m_reduce;
    std::vector<Slot> m_slots;
    std::size_t m_next = 0;
    std::size_t m_inFlight = 0;
};

} // namespace sluice::rt
