// GPU buffers (SSBOs and friends): immutable DSA storage with upload, download and binding.
#pragma once

#include <cstddef>
#include <ranges>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "sluice/format/support/Assert.h"
#include "sluice/format/support/Result.h"
#include "sluice/gpu/Gl.h"

namespace sluice::gpu {

/// A buffer object with immutable storage (glNamedBufferStorage), RAII and move-only.
/// Needs the context that created it to be current for every call, destruction included.
class Buffer {
public:
    /// Allocates `bytes` of uninitialized storage. `label` names it in GL debug messages.
    /// `flags` are glNamedBufferStorage flags; the default allows upload() and download().
    /// GpuOutOfMemory if the GL cannot allocate it (GL_OUT_OF_MEMORY) or the size cannot be
    /// represented; InvalidArgument for zero bytes.
    static Result<Buffer> create(std::size_t bytes, std::string_view label = {},
                                 GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);

    /// Allocates a buffer holding a copy of `data` (any contiguous range of trivially copyable
    /// elements: std::vector, std::array, std::span).
    template <std::ranges::contiguous_range R>
    static Result<Buffer> createFrom(const R& data, std::string_view label = {},
                                     GLbitfield flags = GL_DYNAMIC_STORAGE_BIT) {
        using T = std::ranges::range_value_t<R>;
        static_assert(std::is_trivially_copyable_v<T>, "GPU data must be trivially copyable");
        auto buffer = create(std::ranges::size(data) * sizeof(T), label, flags);
        if (buffer)
            buffer->upload(data);
        return buffer;
    }

    Buffer() = default; ///< empty: id() == 0, size() == 0
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
    ~Buffer();

    GLuint id() const { return m_id; }
    /// Storage size [bytes].
    std::size_t size() const { return m_size; }

    /// Copies `bytes` from `data` to the buffer at `offset` [bytes] (glNamedBufferSubData).
    /// Precondition: the range lies inside the buffer; created with GL_DYNAMIC_STORAGE_BIT.
    void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
    template <std::ranges::contiguous_range R> void upload(const R& data, std::size_t offset = 0) {
        using T = std::ranges::range_value_t<R>;
        static_assert(std::is_trivially_copyable_v<T>, "GPU data must be trivially copyable");
        upload(std::ranges::data(data), std::ranges::size(data) * sizeof(T), offset);
    }

    /// Copies `bytes` at `offset` [bytes] into `out` (glGetNamedBufferSubData; waits for the
    /// GPU). Issues glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT) first, so shader writes
    /// from earlier dispatches are visible. Precondition: the range lies inside the buffer.
    void download(void* out, std::size_t bytes, std::size_t offset = 0) const;
    /// The whole buffer as T values. Precondition: size() is a multiple of sizeof(T).
    template <class T> std::vector<T> download() const {
        static_assert(std::is_trivially_copyable_v<T>, "GPU data must be trivially copyable");
        SLUICE_ASSERT(m_size % sizeof(T) == 0, "Buffer::download: size not a multiple of T");
        std::vector<T> values(m_size / sizeof(T));
        download(values.data(), m_size);
        return values;
    }
    /// `count` T values starting at element `first`.
    template <class T> std::vector<T> download(std::size_t first, std::size_t count) const {
        static_assert(std::is_trivially_copyable_v<T>, "GPU data must be trivially copyable");
        std::vector<T> values(count);
        download(values.data(), count * sizeof(T), first * sizeof(T));
        return values;
    }

    /// Sets every byte to zero (glClearNamedBufferData).
    void clear();
    /// Sets bytes [offset, offset + bytes) to zero (glClearNamedBufferSubData). Precondition:
    /// the range lies in the buffer and both are multiples of 4.
    void clear(std::size_t offset, std::size_t bytes);

    /// glBindBufferBase(target, index): e.g. GL_SHADER_STORAGE_BUFFER and the binding index
    /// from shaders/shared/*.h. Precondition: index below the target's binding limit.
    void bindBase(GLenum target, GLuint index) const;
    /// Binds the whole buffer as the SSBO at `index`.
    void bindStorage(GLuint index) const { bindBase(GL_SHADER_STORAGE_BUFFER, index); }

private:
    void release();

    GLuint m_id = 0;
    std::size_t m_size = 0;
};

} // namespace sluice::gpu
