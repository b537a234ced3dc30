// What the surface passes share on the CPU side (SurfaceReconstructor.cpp, SurfaceBlur.cpp):
// buffers kept from one reconstruction to the next, and the barrier between passes.
#ifndef SLUICE_RT_SURFACE_SURFACE_GPU_H
#define SLUICE_RT_SURFACE_SURFACE_GPU_H

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Gl.h"

namespace sluice::rt::surface {

/// Work groups a dispatch of the surface passes holds at most (Program::dispatchChunked).
inline constexpr std::uint64_t kMaxGroupsPerDispatch = 65535;

/// Makes `buffer` hold at least `bytes`, reusing it when it does (a reconstruction a frame
/// allocates nothing once the sizes settle; a new one gets a quarter more room), and zeroes its
/// first `bytes` when `zeroed`.
inline Result<void> ensureBytes(gpu::Buffer& buffer, std::uint64_t bytes, const char* label,
                                bool zeroed) {
    bytes = std::max<std::uint64_t>(bytes, 4);
    if (buffer.size() < bytes) {
        buffer = {};
        auto created = gpu::Buffer::create(bytes + bytes / 4 / 4 * 4, label);
        if (!created)
            return created.error();
        buffer = std::move(*created);
    }
    if (zeroed)
        buffer.clear(0, bytes);
    return {};
}

/// ensureBytes for `count` uints, zeroed unless a pass writes every one of them; SizeOverflow
/// past what a buffer may hold.
inline Result<void> ensureUints(gpu::Buffer& buffer, std::uint64_t count, const char* label,
                                bool zeroed = true) {
    if (count > std::numeric_limits<std::uint32_t>::max() / 4)
        return fail(ErrorCode::SizeOverflow, std::string("surface: ") + label + " would hold " +
                                                 std::to_string(count) +
                                                 " entries, past the 2^30 a buffer may");
    return ensureBytes(buffer, count * 4, label, zeroed);
}

/// Makes what the passes wrote to storage visible to the next pass and to buffer reads.
inline void barrier() {
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

} // namespace sluice::rt::surface

#endif // SLUICE_RT_SURFACE_SURFACE_GPU_H
