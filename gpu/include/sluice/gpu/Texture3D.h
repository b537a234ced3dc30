// Single-channel float 3D textures (GL_R32F), e.g. SDF grids sampled by the runtime.
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Gl.h"

namespace sluice::gpu {

/// A GL_R32F 3D texture with immutable storage (one mip level), trilinear filtering and
/// clamp-to-edge addressing. Texel (x, y, z) is value x + dims.x * (y + dims.y * z).
/// RAII, move-only; needs its context current.
class Texture3D {
public:
    /// Allocates `dims` [texels] of uninitialized storage. InvalidArgument for a zero
    /// dimension, SizeOverflow above GL_MAX_3D_TEXTURE_SIZE, GpuOutOfMemory if GL cannot
    /// allocate it.
    static Result<Texture3D> createR32F(glm::uvec3 dims, std::string_view label = {});

    Texture3D() = default; ///< empty: id() == 0
    Texture3D(Texture3D&& other) noexcept;
    Texture3D& operator=(Texture3D&& other) noexcept;
    Texture3D(const Texture3D&) = delete;
    Texture3D& operator=(const Texture3D&) = delete;
    ~Texture3D();

    GLuint id() const { return m_id; }
    /// Size [texels].
    glm::uvec3 dims() const { return m_dims; }

    /// Replaces every texel. Precondition: values.size() == dims.x * dims.y * dims.z.
    void upload(std::span<const float> values);
    /// Every texel, x fastest (waits for the GPU; barriers for earlier image writes first).
    std::vector<float> download() const;

    /// Binds for sampling (sampler3D) on texture unit `unit`.
    void bindTexture(GLuint unit) const;
    /// Binds as image3D (layout r32f) on image unit `unit`; access is GL_READ_ONLY,
    /// GL_WRITE_ONLY or GL_READ_WRITE.
    void bindImage(GLuint unit, GLenum access) const;

private:
    void release();

    GLuint m_id = 0;
    glm::uvec3 m_dims{0};
};

} // namespace sluice::gpu
