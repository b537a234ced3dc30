// Forces on static and kinematic colliders: the measured set, the substep's pass and the
// copies read back once their fence has passed.
#include "colliders/ColliderForces.h"

#include "shared/Bodies.h"
#include "shared/Pbf.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {

void ColliderForceMeter::reset(std::size_t colliders, std::uint32_t firstSlot) {
    m_on.assign(colliders, false);
    m_count = 0;
    m_firstSlot = firstSlot;
}

std::uint32_t ColliderForceMeter::slotOf(std::size_t c) const {
    return m_on[c] ? m_firstSlot + std::uint32_t(c) : shared::kNoBody;
}

Result<void> ColliderForceMeter::set(std::size_t c, bool on,
                                     const std::vector<gpu::ShaderDefine>& defines) {
    if (on && !m_pass.id()) {
        auto pass = gpu::Program::compute(
            "pbf_collider_forces.comp", shaders::shaderSource("pbf_collider_forces.comp"), defines);
        if (!pass)
            return pass.error();
        const std::size_t bytes = shared::kMaxColliders * sizeof(shared::GpuColliderForce);
        auto forces = gpu::Buffer::create(bytes, "collider forces");
        if (!forces)
            return forces.error();
        for (Snapshot& s : m_snapshots) {
            auto copy = gpu::Buffer::create(bytes, "collider forces snapshot");
            if (!copy)
                return copy.error();
            s.forces = std::move(*copy);
        }
        m_pass = std::move(*pass);
        m_forces = std::move(*forces);
    }
    if (m_on[c] != on)
        m_count += on ? 1 : -1;
    m_on[c] = on;
    return {};
}

std::uint32_t ColliderForceMeter::run(bool firstSubstep, float substepShare) const {
    m_forces.bindStorage(shared::kBindColliderForces);
    m_pass.set("firstSubstep", firstSubstep ? 1u : 0u);
    m_pass.set("substepShare", substepShare);
    m_pass.use();
    glDispatchCompute(1, 1, 1);
    return 1;
}

void ColliderForceMeter::snapshot(std::uint64_t step, double time) {
    Snapshot& s = m_snapshots[m_next];
    m_next = (m_next + 1) % m_snapshots.size();
    // The step ends with a buffer-update barrier, so the copy sees the pass's writes.
    glCopyNamedBufferSubData(m_forces.id(), s.forces.id(), 0, 0,
                             GLsizeiptr(m_on.size() * sizeof(shared::GpuColliderForce)));
    s.fence = Fence::insert();
    s.step = step;
    s.time = time;
    s.on = m_on;
}

std::optional<ForcesReading> ColliderForceMeter::latest() const {
    if (!any())
        return std::nullopt;
    const Snapshot* s = newestPassed(m_snapshots, m_next);
    if (s == nullptr)
        return std::nullopt;
    const auto records = s->forces.download<shared::GpuColliderForce>(0, s->on.size());
    ForcesReading reading;
    reading.step = s->step;
    reading.time = s->time;
    for (std::size_t c = 0; c < s->on.size(); ++c)
        if (s->on[c])
            reading.colliders.push_back({std::uint32_t(c), records[c].force, records[c].torque});
    return reading;
}

} // namespace sluice::rt
