// Copies in id order: the game's buffers checked, cleared, and written by one pass.
#include "sim/ParticleCopy.h"

#include <string>

#include "shared/Pbf.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {
namespace {

constexpr std::uint64_t kEntryBytes = 16; // vec4

// Whether GL buffer `name` can take `entries` vec4 entries; the error names `what`.
Result<void> checkTarget(std::uint32_t name, std::uint64_t entries, const char* what) {
    const std::string head = std::string("copyParticlesById: ") + what + " buffer ";
    if (name == 0 || !glIsBuffer(name))
        return fail(ErrorCode::InvalidArgument,
                    head + std::to_string(name) + " is no GL buffer of this context");
    GLint64 size = 0;
    glGetNamedBufferParameteri64v(name, GL_BUFFER_SIZE, &size);
    if (std::uint64_t(size) < entries * kEntryBytes)
        return fail(ErrorCode::InvalidArgument, head + std::to_string(name) + " holds " +
                                                    std::to_string(size) + " bytes; " +
                                                    std::to_string(entries) + " ids need " +
                                                    std::to_string(entries * kEntryBytes));
    return {};
}

void clearEntries(std::uint32_t name, std::uint64_t entries) {
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearNamedBufferSubData(name, GL_RGBA32F, 0, GLsizeiptr(entries * kEntryBytes), GL_RGBA,
                              GL_FLOAT, zero);
}

} // namespace

Result<void> IdOrderCopy::run(const ParticleSlots& from, const ParticleCopyTarget& target) {
    if (target.count == 0)
        return {};
    if (auto ok = checkTarget(target.positions, target.count, "positions"); !ok)
        return ok.error();
    if (target.velocities != 0)
        if (auto ok = checkTarget(target.velocities, target.count, "velocities"); !ok)
            return ok.error();
    if (!m_pass.id()) {
        auto pass = gpu::Program::compute("pbf_copy_by_id.comp",
                                          shaders::shaderSource("pbf_copy_by_id.comp"));
        if (!pass)
            return pass.error();
        m_pass = std::move(*pass);
    }
    clearEntries(target.positions, target.count);
    if (target.velocities != 0)
        clearEntries(target.velocities, target.count);
    from.positions->bindStorage(shared::kBindPosIn);
    from.velocities->bindStorage(shared::kBindVelIn);
    from.ids->bindStorage(shared::kBindIdIn);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, shared::kBindPosOut, target.positions);
    // Without velocities the pass writes none; the binding only has to hold a buffer.
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, shared::kBindVelOut,
                     target.velocities != 0 ? target.velocities : target.positions);
    m_pass.set("slots", from.slots);
    m_pass.set("firstId", target.firstId);
    m_pass.set("idCount", target.count);
    m_pass.set("withVelocities", target.velocities != 0 ? 1u : 0u);
    m_pass.use();
    const std::uint32_t groups = (from.slots + shared::kPbfLocalSize - 1) / shared::kPbfLocalSize;
    m_pass.dispatchChunked(glm::uvec3(groups, 1, 1), shared::kPbfMaxGroupsPerDispatch);
    // The game may read the copy any way: as vertices, storage, texels, a copy or a readback.
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    return {};
}

} // namespace sluice::rt
