// Copies of the particles in id order into buffers the game owns (docs/embedding.md, "Copies
// in id order"): the checks of the game's buffers and the pass (pbf_copy_by_id.comp), built on
// first use.
#pragma once

#include <cstdint>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

/// The particle buffers a copy reads: `slots` slots of positions, velocities and ids.
struct ParticleSlots {
    const gpu::Buffer* positions = nullptr;
    const gpu::Buffer* velocities = nullptr;
    const gpu::Buffer* ids = nullptr;
    std::uint32_t slots = 0;
};

class IdOrderCopy {
public:
    /// Clears the target's `count` entries and writes each live particle of `from` whose id lies
    /// in [firstId, firstId + count) into entry id - firstId, w = 1; ends with a barrier for any
    /// later use of the target in this context. InvalidArgument, with nothing written, for a name
    /// that is no buffer or a buffer too small for `count` entries; the pass's build error on first
    /// use.
    Result<void> run(const ParticleSlots& from, const ParticleCopyTarget& target);

private:
    gpu::Program m_pass;
};

} // namespace sluice::rt
