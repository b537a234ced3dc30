// Texel views of buffers (GL_TEXTURE_BUFFER): limits as values, binding.
#include "sluice/gpu/BufferTexture.h"

#include <string>
#include <utility>

#include "DebugState.h"
#include "sluice/format/support/Assert.h"

namespace sluice::gpu {

std::uint64_t BufferTexture::maxTexels() {
    GLint texels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
    return texels > 0 ? std::uint64_t(texels) : 0;
}

namespace {

GLenum glFormat(TexelFormat format) {
    switch (format) {
    case TexelFormat::R32F:
        return GL_R32F;
    case TexelFormat::R32UI:
        return GL_R32UI;
    case TexelFormat::RGBA32F:
        return GL_RGBA32F;
    case TexelFormat::RGBA32UI:
        return GL_RGBA32UI;
    }
    return GL_R32F;
}

} // namespace

std::uint32_t texelBytes(TexelFormat format) {
    return format == TexelFormat::R32F || format == TexelFormat::R32UI ? 4 : 16;
}

Result<BufferTexture> BufferTexture::create(const Buffer& buffer, TexelFormat format,
                                            std::string_view label) {
    const std::string name = label.empty() ? std::string("buffer texture")
                                           : "buffer texture '" + std::string(label) + "'";
    const std::uint64_t bytes = buffer.size();
    const std::uint32_t texel = texelBytes(format);
    if (buffer.id() == 0 || bytes == 0 || bytes % texel != 0)
        return fail(ErrorCode::InvalidArgument, "cannot make " + name + " of " +
                                                    std::to_string(bytes) +
                                                    " bytes: it needs a whole number of " +
                                                    std::to_string(texel) + "-byte texels");
    const std::uint64_t texels = bytes / texel;
    if (texels > maxTexels())
        return fail(ErrorCode::SizeOverflow,
                    "cannot make " + name + " of " + std::to_string(texels) +
                        " texels: GL_MAX_TEXTURE_BUFFER_SIZE is " + std::to_string(maxTexels()));
    BufferTexture texture;
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &texture.m_id);
    glTextureBuffer(texture.m_id, glFormat(format), buffer.id());
    if (!label.empty())
        glObjectLabel(GL_TEXTURE, texture.m_id, labelLength(label), label.data());
    failOnDebugErrors("BufferTexture::create");
    return texture;
}

BufferTexture::BufferTexture(BufferTexture&& other) noexcept : m_id(std::exchange(other.m_id, 0)) {}

BufferTexture& BufferTexture::operator=(BufferTexture&& other) noexcept {
    if (this != &other) {
        release();
        m_id = std::exchange(other.m_id, 0);
    }
    return *this;
}

BufferTexture::~BufferTexture() {
    release();
}

void BufferTexture::release() {
    if (m_id != 0)
        glDeleteTextures(1, &m_id);
    m_id = 0;
}

void BufferTexture::bindTexture(GLuint unit) const {
    SLUICE_ASSERT(m_id != 0, "BufferTexture::bindTexture on an empty texture");
    glBindTextureUnit(unit, m_id);
    failOnDebugErrors("BufferTexture::bindTexture");
}

} // namespace sluice::gpu
