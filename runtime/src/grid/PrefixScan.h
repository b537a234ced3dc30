// Exclusive prefix sum of a uint buffer on the GPU: block scans in shared memory, then each
// block's offset added back (Blelloch 1990). Up to kScanReducedBlocks blocks each work group of
// the add pass sums the totals before its block itself; more blocks have their totals scanned
// recursively first. One dispatch up to kScanBlock elements, two up to kScanBlock *
// kScanReducedBlocks (8 M). (A one-group scan of up to 65,536 elements in one dispatch was
// tried: on an H200 it took 2.5 times as long as three dispatches at 25k, docs/performance.md.)
#pragma once

#include <cstdint>
#include <vector>

#include "shared/Pbf.h"
#include "sluice/format/support/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"
#include "sluice/rt/sim/GpuCommandCount.h"

namespace sluice::rt {

/// What PrefixScan::exclusive scans.
struct ScanInput {
    std::uint32_t count = 0;      ///< outputs written: out[0 .. count)
    std::uint32_t inputCount = 0; ///< inputs read, at most count; the ones after read as 0
    bool clearInput = false;      ///< zero each input read (in must not be out)
};

class PrefixScan {
public:
    /// Compiles the passes and allocates the per-level block totals for up to `maxCount`
    /// elements. `reducedBlocks`: the most blocks whose totals the add pass sums itself (tests
    /// lower it to reach the recursive levels with small inputs).
    static Result<PrefixScan> create(std::uint32_t maxCount,
                                     std::uint32_t reducedBlocks = shared::kScanReducedBlocks);

    /// out[i] = in[0] + ... + in[i - 1] for i < count. `in` and `out` may be the same buffer.
    /// Queues GPU work only; issues the storage barriers it needs, including one at the end.
    GpuCommandCount exclusive(const gpu::Buffer& in, const gpu::Buffer& out,
                              std::uint32_t count) const;
    /// The same with the inputs `what` describes (a shorter input, zeroed as it is read).
    GpuCommandCount exclusive(const gpu::Buffer& in, const gpu::Buffer& out,
                              const ScanInput& what) const;

private:
    GpuCommandCount scanLevel(const gpu::Buffer& in, const gpu::Buffer& out, const ScanInput& what,
                              std::size_t level) const;

    gpu::Program m_block;
    gpu::Program m_add;
    std::vector<gpu::Buffer> m_sums; // level l holds one total per block of level l
    std::uint32_t m_reducedBlocks = 0;
};

} // namespace sluice::rt
