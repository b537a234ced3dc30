// The particles as sphere impostors: the ones that cover a few pixels by two compute passes
// (render_splat.comp: nearest depth per pixel, then the particle of it) and one full-screen
// shading pass, the rest by the rasterised impostor draw over the list the first pass made
// (docs/rendering.md, "Spheres").
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "GlObjects.h"
#include "sluice/format/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"

namespace sluice::rt {

class SphereSplatPass {
public:
    static Result<SphereSplatPass> create();

    /// Reallocates the per-pixel depth image for images of `size` pixels.
    Result<void> resize(glm::uvec2 size);

    /// Draws `particleCount` spheres over the opaque scene into the bound draw framebuffer,
    /// whose depth attachment is `sceneDepth` (sampled by the compute passes, then tested and
    /// written). Needs the frame block, the particle buffers and an empty vertex array bound.
    /// GpuOutOfMemory, drawing nothing, when the list of large spheres cannot grow to
    /// `particleCount`.
    Result<void> draw(std::uint32_t particleCount, GLuint sceneDepth);

private:
    gpu::Program m_nearest;  // render_splat.comp: depths, and the list of large spheres
    gpu::Program m_winner;   // render_splat.comp with SLUICE_SPLAT_WINNER
    gpu::Program m_resolve;  // render_splat_resolve.frag: colour and depth of each winner
    gpu::Program m_listed;   // render_particles with SLUICE_PARTICLE_LIST
    TextureHandle m_depth;   // R32UI nearest window depth bits, ~0u where none
    TextureHandle m_winners; // R32UI the particle of that depth, ~0u where none
    glm::uvec2 m_size{0};
    gpu::Buffer m_list;      // uint per particle of m_capacity
    std::uint32_t m_capacity = 0;
    gpu::Buffer m_args;      // shared::SplatDrawArgs
};

} // namespace sluice::rt
