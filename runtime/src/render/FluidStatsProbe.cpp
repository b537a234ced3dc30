// GPU reduction of the density error and speed, read back through persistently mapped buffers.
#include "sluice/rt/render/FluidStatsProbe.h"

#include <bit>
#include <cstring>

#include "GlObjects.h"
#include "shared/Render.h"
#include "sluice/format/support/Assert.h"
#include "sluice/rt/RuntimeShaders.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

struct FluidStatsProbe::Slot {
    gpu::Buffer sums;     // shared::RenderStats, written by render_stats.comp
    gpu::Buffer readback; // its copy, persistently mapped for reading
    const void* mapped = nullptr;
    Fence fence;
    std::uint64_t step = 0;
    std::uint32_t particles = 0;
};

FluidStatsProbe::FluidStatsProbe() = default;
FluidStatsProbe::FluidStatsProbe(FluidStatsProbe&&) noexcept = default;
FluidStatsProbe& FluidStatsProbe::operator=(FluidStatsProbe&&) noexcept = default;
FluidStatsProbe::~FluidStatsProbe() = default;

Result<FluidStatsProbe> FluidStatsProbe::create(std::size_t slots) {
    SLUICE_ASSERT(slots >= 1, "FluidStatsProbe needs at least one slot");
    FluidStatsProbe probe;
    auto reduce =
        gpu::Program::compute("render_stats.comp", shaders::shaderSource("render_stats.comp"));
    if (!reduce)
        return reduce.error();
    probe.m_reduce = std::move(*reduce);
    constexpr GLbitfield kMapFlags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    for (std::size_t i = 0; i < slots; ++i) {
        auto sums = gpu::Buffer::create(sizeof(shared::RenderStats), "render stats");
        if (!sums)
            return sums.error();
        auto readback =
            gpu::Buffer::create(sizeof(shared::RenderStats), "render stats readback", kMapFlags);
        if (!readback)
            return readback.error();
        Slot slot;
        slot.mapped =
            glMapNamedBufferRange(readback->id(), 0, sizeof(shared::RenderStats), kMapFlags);
        if (slot.mapped == nullptr)
            return fail(ErrorCode::GpuOutOfMemory, "cannot map the statistics readback buffer");
        slot.sums = std::move(*sums);
        slot.readback = std::move(*readback);
        probe.m_slots.push_back(std::move(slot));
    }
    return probe;
}

bool FluidStatsProbe::record(const Simulation& sim) {
    if (m_inFlight == m_slots.size())
        return false;
    Slot& slot = m_slots[m_next];
    slot.step = sim.steps();
    slot.particles = sim.particleCount();
    slot.sums.clear();
    if (slot.particles > 0) {
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        sim.velocityBuffer().bindStorage(shared::kRenderBindVelocities);
        slot.sums.bindStorage(shared::kRenderBindStats);
        m_reduce.set("uCount", slot.particles);
        m_reduce.dispatch(gpu::groupCount(slot.particles, shared::kRenderStatsLocalSize));
    }
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glCopyNamedBufferSubData(slot.sums.id(), slot.readback.id(), 0, 0, sizeof(shared::RenderStats));
    slot.fence = Fence::insert();
    m_next = (m_next + 1) % m_slots.size();
    ++m_inFlight;
    return true;
}

std::optional<FluidStats> FluidStatsProbe::poll(bool wait) {
    std::optional<FluidStats> newest;
    while (m_inFlight > 0) {
        Slot& slot = m_slots[(m_next + m_slots.size() - m_inFlight) % m_slots.size()];
        if (!slot.fence.signalled(wait))
            break;
        shared::RenderStats sums{};
        std::memcpy(&sums, slot.mapped, sizeof sums);
        const double sum = double((std::uint64_t(sums.errorHi) << 32) | sums.errorLo) /
                           double(shared::kRenderStatsFixedScale);
        FluidStats stats;
        stats.step = slot.step;
        stats.particles = slot.particles;
        stats.avgDensityError = slot.particles > 0 ? sum / double(slot.particles) : 0.0;
        stats.maxDensityError = std::bit_cast<float>(sums.errorMaxBits);
        stats.maxSpeed = std::bit_cast<float>(sums.speedMaxBits);
        newest = stats;
        slot.fence.reset();
        --m_inFlight;
    }
    return newest;
}

} // namespace sluice::rt
