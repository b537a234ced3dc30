// A buffer's words read as texels (GL_TEXTURE_BUFFER): shaders fetch them through a texture
// unit (samplerBuffer, texelFetch) instead of a storage block.
#pragma once

#include <cstdint>
#include <string_view>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Gl.h"

namespace sluice::gpu {

/// How a buffer texture reads its buffer's words: texel i is word i (R32F, R32UI; samplerBuffer
/// and usamplerBuffer) or words 4i to 4i + 3 (RGBA32F, RGBA32UI).
enum class TexelFormat { R32F, R32UI, RGBA32F, RGBA32UI };

/// [bytes] One texel of `format`.
std::uint32_t texelBytes(TexelFormat format);

/// A texel view of a whole Buffer. It holds no storage of its own; the buffer must outlive it,
/// and a shader's writes to the buffer need GL_TEXTURE_FETCH_BARRIER_BIT before a fetch sees
/// them. RAII, move-only; needs its context current.
class BufferTexture {
public:
    /// Texels a buffer texture may hold on this GL (GL_MAX_TEXTURE_BUFFER_SIZE; 65536 at least).
    static std::uint64_t maxTexels();

    /// The view of `buffer` as texels of `format`. InvalidArgument for an empty buffer or one
    /// whose size is not a whole number of texels; SizeOverflow for more texels than
    /// maxTexels().
    static Result<BufferTexture> create(const Buffer& buffer, TexelFormat format,
                                        std::string_view label = {});
    /// The view of `buffer` as floats: create(buffer, TexelFormat::R32F, label).
    static Result<BufferTexture> createR32F(const Buffer& buffer, std::string_view label = {}) {
        return create(buffer, TexelFormat::R32F, label);
    }

    BufferTexture() = default; ///< empty: id() == 0
    BufferTexture(BufferTexture&& other) noexcept;
    BufferTexture& operator=(BufferTexture&& other) noexcept;
    BufferTexture(const BufferTexture&) = delete;
    BufferTexture& operator=(const BufferTexture&) = delete;
    ~BufferTexture();

    GLuint id() const { return m_id; }

    /// Binds for fetching (samplerBuffer) on texture unit `unit`.
    void bindTexture(GLuint unit) const;

private:
    void release();

    GLuint m_id = 0;
};

} // namespace sluice::gpu
