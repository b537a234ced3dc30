// GL object creation with labels and error values, and the fence wrapper.
#include "GlObjects.h"

#include <cstdio>
#include <string>

namespace sluice::rt {
namespace {

void label(GLenum type, GLuint id, std::string_view name) {
    if (!name.empty())
        glObjectLabel(type, id, static_cast<GLsizei>(name.size()), name.data());
}

// Drains the GL error queue; true if any error was an out-of-memory one.
bool outOfMemory() {
    bool oom = false;
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError())
        oom = oom || e == GL_OUT_OF_MEMORY;
    return oom;
}

std::string hex(GLenum value) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%x", static_cast<unsigned>(value));
    return text;
}

} // namespace

void deleteTexture(GLuint id) {
    glDeleteTextures(1, &id);
}
void deleteFramebuffer(GLuint id) {
    glDeleteFramebuffers(1, &id);
}
void deleteVertexArray(GLuint id) {
    glDeleteVertexArrays(1, &id);
}
void deleteBuffer(GLuint id) {
    glDeleteBuffers(1, &id);
}

Result<TextureHandle> createTexture2D(GLenum format, glm::uvec2 size, std::string_view name,
                                      bool linear) {
    outOfMemory(); // start from a clean error queue
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    TextureHandle texture(id);
    glTextureStorage2D(id, 1, format, static_cast<GLsizei>(size.x), static_cast<GLsizei>(size.y));
    if (outOfMemory())
        return fail(ErrorCode::GpuOutOfMemory, "cannot allocate the " + std::string(name) +
                                                   " texture (" + std::to_string(size.x) + " x " +
                                                   std::to_string(size.y) + ")");
    const GLint filter = linear ? GL_LINEAR : GL_NEAREST;
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, filter);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, filter);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    label(GL_TEXTURE, id, name);
    return texture;
}

Result<FramebufferHandle> createFramebuffer(GLuint colour, GLuint depth, std::string_view name) {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    FramebufferHandle framebuffer(id);
    if (colour != 0) {
        glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT0, colour, 0);
        glNamedFramebufferDrawBuffer(id, GL_COLOR_ATTACHMENT0);
        glNamedFramebufferReadBuffer(id, GL_COLOR_ATTACHMENT0);
    } else {
        glNamedFramebufferDrawBuffer(id, GL_NONE);
        glNamedFramebufferReadBuffer(id, GL_NONE);
    }
    if (depth != 0)
        glNamedFramebufferTexture(id, GL_DEPTH_ATTACHMENT, depth, 0);
    const GLenum status = glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return fail(ErrorCode::InvalidArgument, "the " + std::string(name) +
                                                    " framebuffer is incomplete (status " +
                                                    hex(status) + ")");
    label(GL_FRAMEBUFFER, id, name);
    return framebuffer;
}

VertexArrayHandle createEmptyVertexArray() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    return VertexArrayHandle(id);
}

Fence Fence::insert() {
    Fence fence;
    fence.m_sync = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    return fence;
}

Fence& Fence::operator=(Fence&& other) noexcept {
    if (this != &other) {
        reset();
        m_sync = std::exchange(other.m_sync, nullptr);
    }
    return *this;
}

bool Fence::signalled(bool wait) const {
    // The flush bit makes sure the fence reaches the GPU, so a waiting call cannot hang.
    const GLuint64 timeout = wait ? GLuint64(10'000'000'000) : 0; // [ns]
    const GLenum status = glClientWaitSync(m_sync, GL_SYNC_FLUSH_COMMANDS_BIT, timeout);
    return status == GL_ALREADY_SIGNALED || status == GL_CONDITION_SATISFIED;
}

void Fence::reset() {
    if (m_sync != nullptr)
        glDeleteSync(m_sync);
    m_sync = nullptr;
}

} // namespace sluice::rt
