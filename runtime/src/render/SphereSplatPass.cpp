// Small spheres in compute, large ones rasterised from a list (render_splat.comp).
#include "SphereSplatPass.h"

#include <array>

#include "shared/Render.h"
#include "sluice/gpu/Gl.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {
namespace {

constexpr std::uint64_t kMaxGroupsPerDispatch = 65535;
constexpr std::uint32_t kNone = 0xffffffffu;

// render_splat.comp with `define` set, or none.
Result<gpu::Program> splatVariant(const char* name, const char* define) {
    const std::array<gpu::ShaderDefine, 1> defines{{{define ? define : "", "1"}}};
    return gpu::Program::compute(name, shaders::shaderSource("render_splat.comp"),
                                 std::span(defines.data(), define ? 1 : 0));
}

} // namespace

Result<SphereSplatPass> SphereSplatPass::create() {
    SphereSplatPass pass;
    const struct {
        gpu::Program* program;
        const char* name;
        const char* define;
    } variants[] = {{&pass.m_nearest, "render_splat (depth)", nullptr},
                    {&pass.m_winner, "render_splat (winner)", "SLUICE_SPLAT_WINNER"},
                    {&pass.m_thickness, "render_splat (thickness)", "SLUICE_SPLAT_THICKNESS"}};
    for (const auto& v : variants) {
        auto program = splatVariant(v.name, v.define);
        if (!program)
            return program.error();
        *v.program = std::move(*program);
    }
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
    auto summed = createTexture2D(GL_R32UI, size, "splat thickness");
    if (!summed)
        return summed.error();
    m_depth = std::move(*depth);
    m_winners = std::move(*winners);
    m_summed = std::move(*summed);
    m_size = size;
    return {};
}

Result<void> SphereSplatPass::reserve(std::uint32_t particleCount) {
    if (particleCount <= m_capacity)
        return {};
    auto list = gpu::Buffer::create(std::size_t(particleCount) * sizeof(std::uint32_t),
                                    "splat list");
    if (!list)
        return list.error();
    m_list = std::move(*list);
    m_capacity = particleCount;
    return {};
}

void SphereSplatPass::bindImages(GLuint sceneDepth) const {
    glBindTextureUnit(shared::kRenderUnitSceneDepth, sceneDepth);
    glBindImageTexture(shared::kRenderImageSplatDepth, m_depth.id(), 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(shared::kRenderImageSplatWinner, m_winners.id(), 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(shared::kRenderImageSplatThickness, m_summed.id(), 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_R32UI);
    m_list.bindStorage(shared::kRenderBindSplatList);
    m_args.bindStorage(shared::kRenderBindSplatArgs);
}

void SphereSplatPass::dispatch(const gpu::Program& program, std::uint32_t particleCount,
                               float radius) const {
    program.set("uRadius", radius);
    program.dispatchChunked(
        glm::uvec3(gpu::groupCount(particleCount, shared::kSplatLocalSize), 1, 1),
        kMaxGroupsPerDispatch);
}

void SphereSplatPass::computeNearest(std::uint32_t particleCount, float radius,
                                     GLuint sceneDepth) {
    glClearTexImage(m_depth.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &kNone);
    const shared::SplatDrawArgs empty{0, 1, 0, 0};
    m_args.upload(&empty, sizeof empty);
    bindImages(sceneDepth);
    // The opaque scene's depth was rendered just before: sampled here.
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    dispatch(m_nearest, particleCount, radius);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void SphereSplatPass::computeWinners(std::uint32_t particleCount, float radius) {
    glClearTexImage(m_winners.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &kNone);
    dispatch(m_winner, particleCount, radius);
}

void SphereSplatPass::computeThickness(std::uint32_t particleCount, float radius,
                                       GLuint sceneDepth) {
    const std::uint32_t zero = 0;
    glClearTexImage(m_summed.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    bindImages(sceneDepth);
    dispatch(m_thickness, particleCount, radius);
}

void SphereSplatPass::bindResults() const {
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT);
    glBindTextureUnit(shared::kRenderUnitSplatDepth, m_depth.id());
    glBindTextureUnit(shared::kRenderUnitSplatWinner, m_winners.id());
    glBindTextureUnit(shared::kRenderUnitSplatThickness, m_summed.id());
}

void SphereSplatPass::drawListed(const gpu::Program& impostors) const {
    m_list.bindStorage(shared::kRenderBindSplatList);
    impostors.use();
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, m_args.id());
    glDrawArraysIndirect(GL_TRIANGLES, nullptr);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
}

Result<void> SphereSplatPass::drawSpheres(std::uint32_t particleCount, float radius,
                                          GLuint sceneDepth) {
    if (particleCount == 0)
        return {};
    if (auto ok = reserve(particleCount); !ok)
        return ok;
    computeNearest(particleCount, radius, sceneDepth);
    computeWinners(particleCount, radius);
    bindResults();
    // Each pixel's winner shaded, with its depth.
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    m_resolve.use();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    // The large ones, rasterised and depth-tested against everything so far.
    glDepthFunc(GL_LESS);
    drawListed(m_listed);
    return {};
}

} // namespace sluice::rt
