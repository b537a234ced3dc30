// Test support: each particle's N(i) as the last substep's neighbour mask records it, decoded
// on the CPU from Simulation::neighbourState() by walking the candidate ranges exactly as the
// GPU's PBF_RANGES_BEGIN walks them (the same shared cell functions, shared/Pbf.h).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt::test {

/// N(i) of one particle as the mask records it.
struct RecordedNeighbours {
    std::uint32_t id = 0;                ///< the particle
    glm::vec3 start{0.0f};               ///< its x* at the substep start, which chose N(i) [m]
    std::uint32_t candidates = 0;        ///< entries of its cell ranges (docs/pbf.md step 3)
    std::vector<std::uint32_t> fromMask; ///< ids whose mask bit is set, visiting order
    std::vector<std::uint32_t> pastMask; ///< ids past the mask's bits that pass the test
};

/// Every particle's recorded neighbours, in sorted order (reads the GPU back).
std::vector<RecordedNeighbours> recordedNeighbours(const Simulation& sim);

} // namespace sluice::rt::test
