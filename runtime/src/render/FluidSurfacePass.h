// The screen-space fluid surface (van der Laan, Green and Sainz 2009, "Screen Space Fluid
// Rendering with Curvature Flow"): the particles' front depth, smoothed with a bilateral filter,
// their summed thickness, and a shading pass with Fresnel reflection and a refraction-like,
// thickness-absorbed view of the scene behind.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "GlObjects.h"
#include "SphereSplatPass.h"
#include "sluice/format/support/Result.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/gpu/Program.h"

namespace sluice::rt {

/// How the surface is smoothed.
struct FluidSurfaceParams {
    std::uint32_t smoothingIterations = 3; ///< bilateral filter passes
    float filterRadius = 0.0f;             ///< spatial radius of the filter [m]
    float depthFalloff = 0.0f;             ///< depth difference that weighs e^-1 [m]
};

/// GPU timers around draw()'s stages (the spheres' depth and thickness, the smoothing, the
/// shading); null ones are skipped.
struct FluidSurfaceTimers {
    gpu::GpuTimer* spheres = nullptr;
    gpu::GpuTimer* smooth = nullptr;
    gpu::GpuTimer* shade = nullptr;
};

/// Owns the fluid's intermediate targets (view depth, its smoothing partner, thickness) at the
/// renderer's image size. Needs the frame block, the particle buffers and an empty vertex array
/// bound when drawing.
class FluidSurfacePass {
public:
    static Result<FluidSurfacePass> create();

    /// Reallocates the targets for images of `size` pixels.
    Result<void> resize(glm::uvec2 size);

    /// Draws the fluid of `particleCount` particles over the opaque scene (`sceneColour`,
    /// `sceneDepth`, textures of the current size) into `output`, which has a colour and a depth
    /// attachment: every pixel of `output` is written, colour and depth. With `splat`, the
    /// spheres of a few pixels go through its compute passes (depth and thickness), the rest
    /// are rasterised; without, every sphere is rasterised. `sphereRadius` is the frame
    /// block's fluidSphereRadius [m].
    void draw(std::uint32_t particleCount, GLuint sceneColour, GLuint sceneDepth, GLuint output,
              const FluidSurfaceParams& params, SphereSplatPass* splat, float sphereRadius,
              const FluidSurfaceTimers& timers = {}) const;

private:
    /// Steps 1 and 2 of draw() through the compute passes; false (nothing drawn) when the list
    /// of large spheres has no room.
    bool drawSpheresSplatted(std::uint32_t particleCount, GLuint sceneDepth,
                             SphereSplatPass& splat, float sphereRadius) const;

    /// Step 3 of draw(): the smoothing passes; the texture that holds the result.
    GLuint smoothDepth(const FluidSurfaceParams& params, gpu::GpuTimer* timer) const;

    gpu::Program m_depthProgram;
    gpu::Program m_thicknessProgram;
    gpu::Program m_depthListed;      // the same two over the compute pass's list
    gpu::Program m_thicknessListed;
    gpu::Program m_depthResolve;     // render_splat_fluid.frag: the compute pass's depths
    gpu::Program m_thicknessResolve; // and thickness
    gpu::Program m_smoothProgram; // render_fluid_smooth.comp
    gpu::Program m_compositeProgram;
    glm::uvec2 m_size{0};
    TextureHandle m_depth;     // R32F view depth [m], 0 where there is no fluid
    TextureHandle m_depthTemp; // R32F, the smoothing's other target
    TextureHandle m_zBuffer;   // depth attachment of the depth pass
    TextureHandle m_thickness; // R32F summed chord length [m]
    FramebufferHandle m_depthTarget;
    FramebufferHandle m_thicknessTarget;
};

} // namespace sluice::rt
