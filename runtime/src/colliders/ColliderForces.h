// Forces on static and kinematic colliders (docs/embedding.md, "Forces on colliders"): which
// colliders are measured, the pass that turns their push sums into force and torque each substep
// (pbf_collider_forces.comp), and the per-step copies read back without waiting.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "render/GlObjects.h"
#include "sluice/format/support/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

class ColliderForceMeter {
public:
    /// `colliders` in the scene, none measured; measured collider c sums into body-sum slot
    /// `firstSlot + c` (after the bodies').
    void reset(std::size_t colliders, std::uint32_t firstSlot);

    bool any() const { return m_count > 0; }
    bool measured(std::size_t c) const { return m_on[c]; }
    /// GpuCollider::forceSlot of collider c: its slot when measured, else kNoBody.
    std::uint32_t slotOf(std::size_t c) const;

    /// Measures collider c or stops; the first call that turns one on builds the pass (with
    /// the step's collider `defines`) and its buffers.
    Result<void> set(std::size_t c, bool on, const std::vector<gpu::ShaderDefine>& defines);

    /// The substep's pass: each measured collider's sums into its force and torque, a share
    /// `substepShare` of the step's mean (started again when `firstSubstep`). Returns the
    /// dispatches issued. Precondition: the parameters, colliders and body sums are bound.
    std::uint32_t run(bool firstSubstep, float substepShare) const;

    /// After a step: queues the copy of the forces and its fence.
    void snapshot(std::uint64_t step, double time);

    /// The newest copy whose fence has passed, one entry per collider measured then.
    std::optional<ForcesReading> latest() const;

private:
    struct Snapshot {
        gpu::Buffer forces;
        Fence fence;
        std::uint64_t step = 0;
        double time = 0.0;
        std::vector<bool> on;
    };
    std::vector<bool> m_on;
    std::uint32_t m_count = 0;
    std::uint32_t m_firstSlot = 0;
    gpu::Program m_pass;
    gpu::Buffer m_forces; // GpuColliderForce[kMaxColliders]
    std::array<Snapshot, 3> m_snapshots;
    std::size_t m_next = 0;
};

} // namespace sluice::rt
