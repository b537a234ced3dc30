// Screen-space fluid: depth, thickness, bilateral smoothing and composite passes.
#include "FluidSurfacePass.h"

#include <array>

#include "shared/Render.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {
namespace {

Result<gpu::Program> particleVariant(const char* name, const char* define) {
    const std::array<gpu::ShaderDefine, 1> defines{{{define, "1"}}};
    return gpu::Program::graphics(name, shaders::shaderSource("render_particles.vert"),
                                  shaders::shaderSource("render_particles.frag"), defines);
}

Result<gpu::Program> fullScreen(const char* name, const char* fragment) {
    return gpu::Program::graphics(name, shaders::shaderSource("render_fullscreen.vert"),
                                  shaders::shaderSource(fragment));
}

} // namespace

Result<FluidSurfacePass> FluidSurfacePass::create() {
    FluidSurfacePass pass;
    auto depth = particleVariant("render_particles (fluid depth)", "SLUICE_FLUID_DEPTH");
    if (!depth)
        return depth.error();
    auto thickness = particleVariant("render_particles (thickness)", "SLUICE_THICKNESS");
    if (!thickness)
        return thickness.error();
    auto smooth = fullScreen("render_fluid_smooth", "render_fluid_smooth.frag");
    if (!smooth)
        return smooth.error();
    auto composite = fullScreen("render_fluid_composite", "render_fluid_composite.frag");
    if (!composite)
        return composite.error();
    pass.m_depthProgram = std::move(*depth);
    pass.m_thicknessProgram = std::move(*thickness);
    pass.m_smoothProgram = std::move(*smooth);
    pass.m_compositeProgram = std::move(*composite);
    return pass;
}

Result<void> FluidSurfacePass::resize(glm::uvec2 size) {
    if (size == m_size)
        return {};
    m_size = {0, 0};
    auto depth = createTexture2D(GL_R32F, size, "fluid depth");
    if (!depth)
        return depth.error();
    auto temp = createTexture2D(GL_R32F, size, "fluid depth (filter)");
    if (!temp)
        return temp.error();
    auto zBuffer = createTexture2D(GL_DEPTH_COMPONENT32F, size, "fluid z");
    if (!zBuffer)
        return zBuffer.error();
    auto thickness = createTexture2D(GL_R32F, size, "fluid thickness");
    if (!thickness)
        return thickness.error();
    auto depthTarget = createFramebuffer(depth->id(), zBuffer->id(), "fluid depth");
    if (!depthTarget)
        return depthTarget.error();
    auto tempTarget = createFramebuffer(temp->id(), 0, "fluid filter");
    if (!tempTarget)
        return tempTarget.error();
    auto smoothTarget = createFramebuffer(depth->id(), 0, "fluid smooth");
    if (!smoothTarget)
        return smoothTarget.error();
    auto thicknessTarget = createFramebuffer(thickness->id(), 0, "fluid thickness");
    if (!thicknessTarget)
        return thicknessTarget.error();
    m_depth = std::move(*depth);
    m_depthTemp = std::move(*temp);
    m_zBuffer = std::move(*zBuffer);
    m_thickness = std::move(*thickness);
    m_depthTarget = std::move(*depthTarget);
    m_depthTempTarget = std::move(*tempTarget);
    m_smoothTarget = std::move(*smoothTarget);
    m_thicknessTarget = std::move(*thicknessTarget);
    m_size = size;
    return {};
}

void FluidSurfacePass::draw(std::uint32_t particleCount, GLuint sceneColour, GLuint sceneDepth,
                            GLuint output, const FluidSurfaceParams& params) const {
    const GLsizei vertices = static_cast<GLsizei>(6 * std::uint64_t(particleCount));
    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const GLfloat far = 1.0f;
    glDisable(GL_CULL_FACE);
    glBindTextureUnit(shared::kRenderUnitSceneDepth, sceneDepth);

    // 1. The front-most sphere's view depth per pixel (the opaque scene tested in the shader).
    glBindFramebuffer(GL_FRAMEBUFFER, m_depthTarget.id());
    glClearNamedFramebufferfv(m_depthTarget.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(m_depthTarget.id(), GL_DEPTH, 0, &far);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    m_depthProgram.use();
    glDrawArrays(GL_TRIANGLES, 0, vertices);

    // 2. Thickness: every sphere's chord along the ray, summed.
    glBindFramebuffer(GL_FRAMEBUFFER, m_thicknessTarget.id());
    glClearNamedFramebufferfv(m_thicknessTarget.id(), GL_COLOR, 0, zero);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    m_thicknessProgram.use();
    glDrawArrays(GL_TRIANGLES, 0, vertices);
    glDisable(GL_BLEND);

    // 3. Bilateral smoothing of the depth, ping-ponging with the filter texture.
    m_smoothProgram.use();
    m_smoothProgram.set("uWorldRadius", params.filterRadius);
    m_smoothProgram.set("uDepthFalloff", params.depthFalloff);
    GLuint smoothed = m_depth.id();
    for (std::uint32_t i = 0; i < params.smoothingIterations; ++i) {
        const bool toTemp = i % 2 == 0;
        glBindFramebuffer(GL_FRAMEBUFFER, toTemp ? m_depthTempTarget.id() : m_smoothTarget.id());
        glBindTextureUnit(shared::kRenderUnitFluidDepth, smoothed);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        smoothed = toTemp ? m_depthTemp.id() : m_depth.id();
    }

    // 4. Shading over the scene, with the fluid's depth, into the output.
    glBindFramebuffer(GL_FRAMEBUFFER, output);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS); // every pixel is written; the shader chose fluid or scene
    glDepthMask(GL_TRUE);
    glBindTextureUnit(shared::kRenderUnitSceneColour, sceneColour);
    glBindTextureUnit(shared::kRenderUnitFluidDepth, smoothed);
    glBindTextureUnit(shared::kRenderUnitThickness, m_thickness.id());
    m_compositeProgram.use();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthFunc(GL_LESS);
}

} // namespace sluice::rt
