// GPU buffers: allocation with out-of-memory reported as a value, transfers and binding.
#include "sluice/gpu/Buffer.h"

#include <cstdint>
#include <limits>
#include <string>

#include "DebugState.h"

namespace sluice::gpu {

Result<Buffer> Buffer::create(std::size_t bytes, std::string_view label, GLbitfield flags) {
    const std::string name =
        label.empty() ? std::string("buffer") : "buffer '" + std::string(label) + "'";
    if (bytes == 0)
        return fail(ErrorCode::InvalidArgument, "cannot allocate " + name + " of 0 bytes");
    if (bytes > static_cast<std::size_t>(std::numeric_limits<GLsizeiptr>::max()))
        return fail(ErrorCode::GpuOutOfMemory,
                    "cannot allocate " + name + " of " + std::to_string(bytes) + " bytes");

    Buffer buffer;
    GLenum error = GL_NO_ERROR;
    {
        // GL_OUT_OF_MEMORY comes back as a value here, so keep it out of the debug log.
        DebugMute mute;
        clearGlErrors();
        glCreateBuffers(1, &buffer.m_id);
        glNamedBufferStorage(buffer.m_id, static_cast<GLsizeiptr>(bytes), nullptr, flags);
        error = glGetError();
        clearGlErrors();
    }
    if (error != GL_NO_ERROR) {
        const double mib = static_cast<double>(bytes) / (1024.0 * 1024.0);
        if (error == GL_OUT_OF_MEMORY)
            return fail(ErrorCode::GpuOutOfMemory,
                        "the GPU could not allocate " + name + " of " + std::to_string(bytes) +
                            " bytes (" + std::to_string(mib) +
                            " MiB); lower the resolution or free GPU memory");
        SLUICE_ASSERT(error == GL_NO_ERROR, "glNamedBufferStorage failed (bad storage flags?)");
    }
    buffer.m_size = bytes;
    if (!label.empty())
        glObjectLabel(GL_BUFFER, buffer.m_id, labelLength(label), label.data());
    failOnDebugErrors("Buffer::create");
    return buffer;
}

Buffer::Buffer(Buffer&& other) noexcept
    : m_id(std::exchange(other.m_id, 0)), m_size(std::exchange(other.m_size, 0)) {}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
    if (this != &other) {
        release();
        m_id = std::exchange(other.m_id, 0);
        m_size = std::exchange(other.m_size, 0);
    }
    return *this;
}

Buffer::~Buffer() {
    release();
}

void Buffer::release() {
    if (m_id != 0)
        glDeleteBuffers(1, &m_id);
    m_id = 0;
    m_size = 0;
}

void Buffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
    SLUICE_ASSERT(m_id != 0, "Buffer::upload on an empty buffer");
    SLUICE_ASSERT(offset <= m_size && bytes <= m_size - offset,
                  "Buffer::upload: range outside the buffer");
    if (bytes == 0)
        return;
    glNamedBufferSubData(m_id, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
    failOnDebugErrors("Buffer::upload");
}

void Buffer::download(void* out, std::size_t bytes, std::size_t offset) const {
    SLUICE_ASSERT(m_id != 0, "Buffer::download on an empty buffer");
    SLUICE_ASSERT(offset <= m_size && bytes <= m_size - offset,
                  "Buffer::download: range outside the buffer");
    if (bytes == 0)
        return;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(m_id, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes),
                            out);
    failOnDebugErrors("Buffer::download");
}

void Buffer::clear() {
    SLUICE_ASSERT(m_id != 0, "Buffer::clear on an empty buffer");
    const std::uint8_t zero = 0;
    glClearNamedBufferData(m_id, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &zero);
    failOnDebugErrors("Buffer::clear");
}

void Buffer::clear(std::size_t offset, std::size_t bytes) {
    SLUICE_ASSERT(m_id != 0, "Buffer::clear on an empty buffer");
    SLUICE_ASSERT(offset % 4 == 0 && bytes % 4 == 0 && bytes <= m_size && offset <= m_size - bytes,
                  "Buffer::clear: range outside the buffer or not 4-byte aligned");
    if (bytes == 0)
        return;
    const std::uint32_t zero = 0;
    glClearNamedBufferSubData(m_id, GL_R32UI, GLintptr(offset), GLsizeiptr(bytes), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero);
    failOnDebugErrors("Buffer::clear");
}

void Buffer::bindBase(GLenum target, GLuint index) const {
    SLUICE_ASSERT(m_id != 0, "Buffer::bindBase on an empty buffer");
    glBindBufferBase(target, index, m_id);
    failOnDebugErrors("Buffer::bindBase");
}

} // namespace sluice::gpu
