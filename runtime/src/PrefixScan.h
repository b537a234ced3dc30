// Exclusive prefix sum of a uint buffer on the GPU: block scans in shared memory, the block
// totals scanned recursively, then added back (Blelloch 1990).
#pragma once

#include <cstdint>
#include <vector>

#include "sluice/format/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"

namespace sluice::rt {

class PrefixScan {
public:
    /// Compiles the two passes and allocates the per-level block totals for up to `maxCount`
    /// elements.
    static Result<PrefixScan> create(std::uint32_t maxCount);

    /// out[i] = in[0] + ... + in[i - 1] for i < count. `in` and `out` may be the same buffer.
    /// Queues GPU work only; issues the storage barriers it needs, including one at the end.
    void exclusive(const gpu::Buffer& in, const gpu::Buffer& out, std::uint32_t count) const;

private:
    void scanLevel(const gpu::Buffer& in, const gpu::Buffer& out, std::uint32_t count,
                   std::size_t level) const;

    gpu::Program m_block;
    gpu::Program m_add;
    std::vector<gpu::Buffer> m_sums; // level l holds one total per block of level l
};

} // namespace sluice::rt
