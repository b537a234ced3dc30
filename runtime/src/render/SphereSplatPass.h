// The particles' spheres that cover a few pixels, drawn by compute passes (render_splat.comp):
// the nearest hit per pixel, then the particle of it, or the fluid surface's summed thickness;
// the rest listed for the rasterised impostor draw (docs/rendering.md, "Spheres"). The sphere
// mode's frame is drawSpheres(); the fluid surface (FluidSurfacePass) uses the parts.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "GlObjects.h"
#include "sluice/format/support/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"

namespace sluice::rt {

class SphereSplatPass {
public:
    static Result<SphereSplatPass> create();

    /// Reallocates the per-pixel images for images of `size` pixels.
    Result<void> resize(glm::uvec2 size);

    /// Makes room to list up to `particleCount` large spheres. GpuOutOfMemory when it cannot:
    /// the caller then rasterises every sphere.
    Result<void> reserve(std::uint32_t particleCount);

    /// The nearest hit of each pixel among `particleCount` spheres of `radius` [m] in front of
    /// `sceneDepth` (window depth, sampled), into the nearest-depth image; the spheres larger
    /// than the compute passes draw are listed. Needs the frame block and the particle buffers
    /// bound, and reserve(particleCount) to have succeeded.
    void computeNearest(std::uint32_t particleCount, float radius, GLuint sceneDepth);
    /// After computeNearest with the same arguments: the lowest particle index of each pixel's
    /// nearest hit.
    void computeWinners(std::uint32_t particleCount, float radius);
    /// The fluid surface's thickness: every small sphere's chord in front of `sceneDepth`,
    /// summed. After computeNearest with the same arguments (it skips the listed spheres).
    void computeThickness(std::uint32_t particleCount, float radius, GLuint sceneDepth);
    /// Binds the images the compute passes wrote to their texture units (shared/Render.h), for
    /// the full-screen passes that resolve them; issues the barrier they need.
    void bindResults() const;
    /// Draws the listed spheres with `impostors` (a render_particles variant compiled with
    /// SLUICE_PARTICLE_LIST), with the GL state the caller set.
    void drawListed(const gpu::Program& impostors) const;

    /// The sphere mode: draws `particleCount` spheres over the opaque scene into the bound
    /// draw framebuffer, whose depth attachment is `sceneDepth` (sampled by the compute passes,
    /// then tested and written). Errors as reserve(), drawing nothing.
    Result<void> drawSpheres(std::uint32_t particleCount, float radius, GLuint sceneDepth);

private:
    void bindImages(GLuint sceneDepth) const;
    void dispatch(const gpu::Program& program, std::uint32_t particleCount, float radius) const;

    gpu::Program m_nearest;   // render_splat.comp: depths, and the list of large spheres
    gpu::Program m_winner;    // with SLUICE_SPLAT_WINNER
    gpu::Program m_thickness; // with SLUICE_SPLAT_THICKNESS
    gpu::Program m_resolve;   // render_splat_resolve.frag: colour and depth of each winner
    gpu::Program m_listed;    // render_particles with SLUICE_PARTICLE_LIST
    TextureHandle m_depth;    // R32UI nearest window depth bits, ~0u where none
    TextureHandle m_winners;  // R32UI the particle of that depth, ~0u where none
    TextureHandle m_summed;   // R32UI thickness, kSplatThicknessScale
    glm::uvec2 m_size{0};
    gpu::Buffer m_list;       // uint per particle of m_capacity
    std::uint32_t m_capacity = 0;
    gpu::Buffer m_args;       // shared::SplatDrawArgs
};

} // namespace sluice::rt
