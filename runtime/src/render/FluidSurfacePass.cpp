// Screen-space fluid: depth, thickness, bilateral smoothing and composite passes.
#include "FluidSurfacePass.h"

#include <array>

#include "shared/Render.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {
namespace {

Result<gpu::Program> particleVariant(const char* name, const char* define, bool listed = false) {
    const std::array<gpu::ShaderDefine, 2> defines{{{define, "1"}, {"SLUICE_PARTICLE_LIST", "1"}}};
    return gpu::Program::graphics(name, shaders::shaderSource("render_particles.vert"),
                                  shaders::shaderSource("render_particles.frag"),
                                  std::span(defines.data(), listed ? 2 : 1));
}

Result<gpu::Program> fullScreen(const char* name, const char* fragment,
                                std::span<const gpu::ShaderDefine> defines = {}) {
    return gpu::Program::graphics(name, shaders::shaderSource("render_fullscreen.vert"),
                                  shaders::shaderSource(fragment), defines);
}

} // namespace

Result<FluidSurfacePass> FluidSurfacePass::create() {
    FluidSurfacePass pass;
    const std::array<gpu::ShaderDefine, 1> thicknessDefine{{{"SLUICE_THICKNESS", "1"}}};
    struct Built {
        gpu::Program* program;
        Result<gpu::Program> built;
    } programs[] = {
        {&pass.m_depthProgram,
         particleVariant("render_particles (fluid depth)", "SLUICE_FLUID_DEPTH")},
        {&pass.m_thicknessProgram,
         particleVariant("render_particles (thickness)", "SLUICE_THICKNESS")},
        {&pass.m_depthListed,
         particleVariant("render_particles (fluid depth, listed)", "SLUICE_FLUID_DEPTH", true)},
        {&pass.m_thicknessListed,
         particleVariant("render_particles (thickness, listed)", "SLUICE_THICKNESS", true)},
        {&pass.m_depthResolve, fullScreen("render_splat_fluid (depth)", "render_splat_fluid.frag")},
        {&pass.m_thicknessResolve,
         fullScreen("render_splat_fluid (thickness)", "render_splat_fluid.frag", thicknessDefine)},
        {&pass.m_smoothProgram,
         gpu::Program::compute("render_fluid_smooth.comp",
                               shaders::shaderSource("render_fluid_smooth.comp"))},
        {&pass.m_compositeProgram,
         fullScreen("render_fluid_composite", "render_fluid_composite.frag")},
    };
    for (Built& p : programs) {
        if (!p.built)
            return p.built.error();
        *p.program = std::move(*p.built);
    }
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
    auto thicknessTarget = createFramebuffer(thickness->id(), 0, "fluid thickness");
    if (!thicknessTarget)
        return thicknessTarget.error();
    m_depth = std::move(*depth);
    m_depthTemp = std::move(*temp);
    m_zBuffer = std::move(*zBuffer);
    m_thickness = std::move(*thickness);
    m_depthTarget = std::move(*depthTarget);
    m_thicknessTarget = std::move(*thicknessTarget);
    m_size = size;
    return {};
}

// Steps 1 and 2 with the spheres of a few pixels in compute: their nearest depth and summed
// thickness resolved into the targets, then the listed large spheres rasterised over them
// (depth-tested, or added).
bool FluidSurfacePass::drawSpheresSplatted(std::uint32_t particleCount, GLuint sceneDepth,
                                           SphereSplatPass& splat, float sphereRadius) const {
    if (particleCount == 0 || !splat.reserve(particleCount))
        return false;
    splat.computeNearest(particleCount, sphereRadius, sceneDepth);
    splat.computeThickness(particleCount, sphereRadius, sceneDepth);
    splat.bindResults();
    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const GLfloat far = 1.0f;
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glBindFramebuffer(GL_FRAMEBUFFER, m_depthTarget.id());
    glClearNamedFramebufferfv(m_depthTarget.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(m_depthTarget.id(), GL_DEPTH, 0, &far);
    glDepthFunc(GL_ALWAYS);
    m_depthResolve.use();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthFunc(GL_LESS);
    splat.drawListed(m_depthListed);

    glBindFramebuffer(GL_FRAMEBUFFER, m_thicknessTarget.id());
    glDisable(GL_DEPTH_TEST);
    m_thicknessResolve.use(); // every pixel: no clear needed
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    splat.drawListed(m_thicknessListed);
    glDisable(GL_BLEND);
    return true;
}

/// Step 3 of draw(): params.smoothingIterations passes of the bilateral filter in compute,
/// ping-ponging between the depth and the filter texture; returns the one holding the result.
GLuint FluidSurfacePass::smoothDepth(const FluidSurfaceParams& params,
                                     gpu::GpuTimer* timer) const {
    if (timer)
        timer->begin();
    m_smoothProgram.set("uWorldRadius", params.filterRadius);
    m_smoothProgram.set("uDepthFalloff", params.depthFalloff);
    const glm::uvec3 tiles(gpu::groupCount(m_size.x, shared::kFluidSmoothTile),
                           gpu::groupCount(m_size.y, shared::kFluidSmoothTile), 1);
    GLuint smoothed = m_depth.id();
    for (std::uint32_t i = 0; i < params.smoothingIterations; ++i) {
        const GLuint target = i % 2 == 0 ? m_depthTemp.id() : m_depth.id();
        // The depth (and thickness) targets were rendered to, or the previous pass stored.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        glBindTextureUnit(shared::kRenderUnitFluidDepth, smoothed);
        glBindImageTexture(shared::kRenderImageFluidSmooth, target, 0, GL_FALSE, 0, GL_WRITE_ONLY,
                           GL_R32F);
        m_smoothProgram.dispatch(tiles);
        smoothed = target;
    }
    // The composite samples the result; the next frame clears and renders into the targets.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    if (timer)
        timer->end();
    return smoothed;
}

void FluidSurfacePass::draw(std::uint32_t particleCount, GLuint sceneColour, GLuint sceneDepth,
                            GLuint output, const FluidSurfaceParams& params,
                            SphereSplatPass* splat, float sphereRadius,
                            const FluidSurfaceTimers& timers) const {
    const auto begin = [](gpu::GpuTimer* t) {
        if (t)
            t->begin();
    };
    const auto end = [](gpu::GpuTimer* t) {
        if (t)
            t->end();
    };
    const GLsizei vertices = static_cast<GLsizei>(6 * std::uint64_t(particleCount));
    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const GLfloat far = 1.0f;
    glDisable(GL_CULL_FACE);
    glBindTextureUnit(shared::kRenderUnitSceneDepth, sceneDepth);

    begin(timers.spheres);
    if (splat == nullptr ||
        !drawSpheresSplatted(particleCount, sceneDepth, *splat, sphereRadius)) {
        // 1. The front-most sphere's view depth per pixel (the opaque scene tested in the
        // shader).
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
    }

    end(timers.spheres);

    // 3. Bilateral smoothing of the depth.
    const GLuint smoothed = smoothDepth(params, timers.smooth);

    // 4. Shading over the scene, with the fluid's depth, into the output.
    begin(timers.shade);
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
    end(timers.shade);
}

} // namespace sluice::rt
