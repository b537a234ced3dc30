// Small spheres in compute, large ones rasterised from a list (render_splat.comp).
#include "SphereSplatPass.h"

#include <array>

#include "shared/Render.h"
#include "sluice/gpu/Gl.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {
namespace {

constexpr std::uint64_t kMaxGroupsPerDispatch = 65535;

Result<gpu::Program> splatVariant(const char* name, bool winner) {
    const std::array<gpu::ShaderDefine, 1> defines{{{"SLUICE_SPLAT_WINNER", "1"}}};
    return gpu::Program::compute(
        name, shaders::shaderSource("render_splat.comp"),
        winner ? std::span<const gpu::ShaderDefine>(defines) : std::span<const gpu::ShaderDefine>());
}

} // namespace

Result<SphereSplatPass> SphereSplatPass::create() {
    SphereSplatPass pass;
    auto nearest = splatVariant("render_splat (depth)", false);
    if (!nearest)
        return nearest.error();
    auto winner = splatVariant("render_splat (winner)", true);
    if (!winner)
        return winner.error();
    auto resolve = gpu::Program::graphics("render_splat_resolve",
                                          shaders::shaderSource("render_fullscreen.vert"),
                                          shaders::shaderSource("render_splat_resolve.frag"));
    if (!resolve)
        return resolve.error();
    const std::array<gpu::ShaderDefine, 1> listDefine{{{"SLUICE_PARTICLE_LIST", "1"}}};
    auto listed = gpu::Program::graphics(
        "render_particles (listed)", shaders::shaderSource("render_particles.vert"),
        shaders::shaderSource("render_particles.frag"), listDefine);
    if (!listed)
        return listed.error();
    auto args = gpu::Buffer::create(sizeof(shared::SplatDrawArgs), "splat draw args");
    if (!args)
        return args.error();
    pass.m_nearest = std::move(*nearest);
    pass.m_winner = std::move(*winner);
    pass.m_resolve = std::move(*resolve);
    pass.m_listed = std::move(*listed);
    pass.m_args = std::move(*args);
    return pass;
}

Result<void> SphereSplatPass::resize(glm::uvec2 size) {
    if (size == m_size)
        return {};
    auto depth = createTexture2D(GL_R32UI, size, "splat nearest depth");
    if (!depth)
        return depth.error();
    auto winners = createTexture2D(GL_R32UI, size, "splat winners");
    if (!winners)
        return winners.error();
    m_depth = std::move(*depth);
    m_winners = std::move(*winners);
    m_size = size;
    return {};
}

Result<void> SphereSplatPass::draw(std::uint32_t particleCount, GLuint sceneDepth) {
    if (particleCount == 0)
        return {};
    if (particleCount > m_capacity) {
        auto list = gpu::Buffer::create(std::size_t(particleCount) * sizeof(std::uint32_t),
                                        "splat list");
        if (!list)
            return list.error();
        m_list = std::move(*list);
        m_capacity = particleCount;
    }
    const std::uint32_t none = 0xffffffffu;
    glClearTexImage(m_depth.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
    glClearTexImage(m_winners.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
    const shared::SplatDrawArgs empty{0, 1, 0, 0};
    m_args.upload(&empty, sizeof empty);
    glBindTextureUnit(shared::kRenderUnitSceneDepth, sceneDepth);
    glBindImageTexture(shared::kRenderImageSplatDepth, m_depth.id(), 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(shared::kRenderImageSplatWinner, m_winners.id(), 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_R32UI);
    m_list.bindStorage(shared::kRenderBindSplatList);
    m_args.bindStorage(shared::kRenderBindSplatArgs);
    const glm::uvec3 groups(gpu::groupCount(particleCount, shared::kSplatLocalSize), 1, 1);
    // The opaque scene's depth was rendered just before: sampled here, written again below.
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    m_nearest.dispatchChunked(groups, kMaxGroupsPerDispatch);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    m_winner.dispatchChunked(groups, kMaxGroupsPerDispatch);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT);

    // Each pixel's winner shaded, with its depth.
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glBindTextureUnit(shared::kRenderUnitSplatDepth, m_depth.id());
    glBindTextureUnit(shared::kRenderUnitSplatWinner, m_winners.id());
    m_resolve.use();
    glDrawArrays(GL_TRIANGLES, 0, 3);

    // The large ones, rasterised and depth-tested against everything so far.
    glDepthFunc(GL_LESS);
    m_listed.use();
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, m_args.id());
    glDrawArraysIndirect(GL_TRIANGLES, nullptr);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    return {};
}

} // namespace sluice::rt
