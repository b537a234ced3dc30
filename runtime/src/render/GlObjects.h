// Small RAII handles for the GL objects the renderer needs beyond the gpu library: 2D textures,
// framebuffers, an empty vertex array, a pixel-pack buffer and a fence. Move-only; each needs
// its context current, destruction included.
#pragma once

#include <cstddef>
#include <string_view>
#include <utility>

#include <glm/glm.hpp>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Gl.h"

namespace sluice::rt {

/// Owns one GL name and deletes it with `Deleter` (a function of the name).
template <void (*Deleter)(GLuint)> class GlHandle {
public:
    GlHandle() = default;
    explicit GlHandle(GLuint id) : m_id(id) {}
    GlHandle(GlHandle&& other) noexcept : m_id(std::exchange(other.m_id, 0)) {}
    GlHandle& operator=(GlHandle&& other) noexcept {
        if (this != &other) {
            reset();
            m_id = std::exchange(other.m_id, 0);
        }
        return *this;
    }
    GlHandle(const GlHandle&) = delete;
    GlHandle& operator=(const GlHandle&) = delete;
    ~GlHandle() { reset(); }

    GLuint id() const { return m_id; }
    void reset() {
        if (m_id != 0)
            Deleter(m_id);
        m_id = 0;
    }

private:
    GLuint m_id = 0;
};

void deleteTexture(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteBuffer(GLuint id);

using TextureHandle = GlHandle<deleteTexture>;
using FramebufferHandle = GlHandle<deleteFramebuffer>;
using VertexArrayHandle = GlHandle<deleteVertexArray>;
using BufferHandle = GlHandle<deleteBuffer>;

/// A 2D texture with immutable storage of `format` (GL_RGBA8, GL_R32F, GL_DEPTH_COMPONENT32F),
/// nearest filtering unless `linear`, clamped to the edge. GpuOutOfMemory if GL cannot
/// allocate it.
Result<TextureHandle> createTexture2D(GLenum format, glm::uvec2 size, std::string_view label,
                                      bool linear = false);

/// A framebuffer with the given colour attachment (0 for none) and depth attachment (0 for
/// none). InvalidArgument (with the GL status) if it is not complete.
Result<FramebufferHandle> createFramebuffer(GLuint colour, GLuint depth, std::string_view label);

/// An empty vertex array: the render programs build their vertices from gl_VertexID.
VertexArrayHandle createEmptyVertexArray();

/// A GL fence sync object (RAII, move-only).
class Fence {
public:
    Fence() = default;
    /// Inserts a fence after every command issued so far.
    static Fence insert();
    Fence(Fence&& other) noexcept : m_sync(std::exchange(other.m_sync, nullptr)) {}
    Fence& operator=(Fence&& other) noexcept;
    Fence(const Fence&) = delete;
    Fence& operator=(const Fence&) = delete;
    ~Fence() { reset(); }

    bool pending() const { return m_sync != nullptr; }
    /// True once the GPU passed the fence; `wait` blocks until it does. Precondition: pending().
    bool signalled(bool wait) const;
    void reset();

private:
    GLsync m_sync = nullptr;
};

/// The newest entry of a ring of fenced copies (each with a `fence`) whose fence has passed,
/// without waiting: the entry before `next` (the next to be written), then the ones before it;
/// null when none has. latestBodies and latestForces read their copies through it.
template <class Ring> const typename Ring::value_type* newestPassed(const Ring& ring,
                                                                   std::size_t next) {
    for (std::size_t back = 1; back <= ring.size(); ++back) {
        const auto& entry = ring[(next + ring.size() - back) % ring.size()];
        if (entry.fence.pending() && entry.fence.signalled(false))
            return &entry;
    }
    return nullptr;
}

} // namespace sluice::rt
