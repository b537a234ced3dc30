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

Result<BufferTexture> BufferTexture::createR32F(const Buffer& buffer, std::string_view label) {
    const std::string name = label.empty() ? std::string("buffer texture")
                                           : "buffer texture '" + std::string(label) + "'";
    const std::uint64_t bytes = buffer.size();
    if (buffer.id() == 0 || bytes == 0 || bytes % sizeof(float) != 0)
        return fail(ErrorCode::InvalidArgument, "cannot make " + name + " of " +
                                                    std::to_string(bytes) +
                                                    " bytes: it needs a whole number of floats");
    const std::uint64_t texels = bytes / sizeof(float);
    if (texels > maxTexels())
        return fail(ErrorCode::SizeOverflow,
                    "cannot make " + name + " of " + std::to_string(texels) +
                        " texels: GL_MAX_TEXTURE_BUFFER_SIZE is " + std::to_string(maxTexels()));
    BufferTexture texture;
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &texture.m_id);
    glTextureBuffer(texture.m_id, GL_R32F, buffer.id());
    if (!label.empty())
        glObjectLabel(GL_TEXTURE, texture.m_id, labelLength(label), label.data());
    failOnDebugErrors("BufferTexture::createR32F");
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
