// GL_R32F 3D textures: allocation with limits and out-of-memory as values, transfers, binding.
#include "sluice/gpu/Texture3D.h"

#include <string>
#include <utility>

#include "DebugState.h"
#include "sluice/format/support/Assert.h"

namespace sluice::gpu {
namespace {

std::string dimsText(glm::uvec3 dims) {
    return std::to_string(dims.x) + "x" + std::to_string(dims.y) + "x" + std::to_string(dims.z);
}

} // namespace

Result<Texture3D> Texture3D::createR32F(glm::uvec3 dims, std::string_view label) {
    const std::string name =
        (label.empty() ? std::string("3D texture") : "3D texture '" + std::string(label) + "'") +
        " of " + dimsText(dims) + " texels";
    if (dims.x == 0 || dims.y == 0 || dims.z == 0)
        return fail(ErrorCode::InvalidArgument, "cannot allocate " + name + ": zero size");
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &maxSize);
    const auto limit = static_cast<glm::uint>(maxSize);
    if (dims.x > limit || dims.y > limit || dims.z > limit)
        return fail(ErrorCode::SizeOverflow, "cannot allocate " + name +
                                                 ": GL_MAX_3D_TEXTURE_SIZE is " +
                                                 std::to_string(maxSize));

    Texture3D texture;
    GLenum error = GL_NO_ERROR;
    {
        DebugMute mute; // GL_OUT_OF_MEMORY comes back as a value
        clearGlErrors();
        glCreateTextures(GL_TEXTURE_3D, 1, &texture.m_id);
        glTextureStorage3D(texture.m_id, 1, GL_R32F, static_cast<GLsizei>(dims.x),
                           static_cast<GLsizei>(dims.y), static_cast<GLsizei>(dims.z));
        error = glGetError();
        clearGlErrors();
    }
    if (error == GL_OUT_OF_MEMORY)
        return fail(ErrorCode::GpuOutOfMemory, "the GPU could not allocate " + name +
                                                   "; lower the resolution or free GPU memory");
    SLUICE_ASSERT(error == GL_NO_ERROR, "glTextureStorage3D failed");
    texture.m_dims = dims;
    glTextureParameteri(texture.m_id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(texture.m_id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture.m_id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture.m_id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture.m_id, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    if (!label.empty())
        glObjectLabel(GL_TEXTURE, texture.m_id, labelLength(label), label.data());
    failOnDebugErrors("Texture3D::createR32F");
    return texture;
}

Texture3D::Texture3D(Texture3D&& other) noexcept
    : m_id(std::exchange(other.m_id, 0)), m_dims(std::exchange(other.m_dims, glm::uvec3(0))) {}

Texture3D& Texture3D::operator=(Texture3D&& other) noexcept {
    if (this != &other) {
        release();
        m_id = std::exchange(other.m_id, 0);
        m_dims = std::exchange(other.m_dims, glm::uvec3(0));
    }
    return *this;
}

Texture3D::~Texture3D() {
    release();
}

void Texture3D::release() {
    if (m_id != 0)
        glDeleteTextures(1, &m_id);
    m_id = 0;
    m_dims = glm::uvec3(0);
}

void Texture3D::upload(std::span<const float> values) {
    SLUICE_ASSERT(m_id != 0, "Texture3D::upload on an empty texture");
    SLUICE_ASSERT(values.size() == std::size_t{m_dims.x} * m_dims.y * m_dims.z,
                  "Texture3D::upload: value count differs from dims");
    // Rows of float are 4-byte aligned, the default unpack alignment; reset it anyway.
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage3D(m_id, 0, 0, 0, 0, static_cast<GLsizei>(m_dims.x),
                        static_cast<GLsizei>(m_dims.y), static_cast<GLsizei>(m_dims.z), GL_RED,
                        GL_FLOAT, values.data());
    failOnDebugErrors("Texture3D::upload");
}

std::vector<float> Texture3D::download() const {
    SLUICE_ASSERT(m_id != 0, "Texture3D::download on an empty texture");
    std::vector<float> values(std::size_t{m_dims.x} * m_dims.y * m_dims.z);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(m_id, 0, GL_RED, GL_FLOAT,
                      static_cast<GLsizei>(values.size() * sizeof(float)), values.data());
    failOnDebugErrors("Texture3D::download");
    return values;
}

void Texture3D::bindTexture(GLuint unit) const {
    SLUICE_ASSERT(m_id != 0, "Texture3D::bindTexture on an empty texture");
    glBindTextureUnit(unit, m_id);
    failOnDebugErrors("Texture3D::bindTexture");
}

void Texture3D::bindImage(GLuint unit, GLenum access) const {
    SLUICE_ASSERT(m_id != 0, "Texture3D::bindImage on an empty texture");
    glBindImageTexture(unit, m_id, 0, GL_TRUE, 0, access, GL_R32F);
    failOnDebugErrors("Texture3D::bindImage");
}

} // namespace sluice::gpu
