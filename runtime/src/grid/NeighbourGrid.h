// Private: the neighbour grid's part of a Simulation's state (docs/pbf.md, step 3): the buckets
// (a dense grid over the domain box or a hash table), the counting sort's buffers, each
// particle's neighbour mask, and the texel views the neighbour passes fetch through.
#pragma once

#include <cstdint>
#include <memory>

#include "grid/PrefixScan.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/BufferTexture.h"

namespace sluice::rt {

struct NeighbourGrid {
    std::uint32_t tableSize = 0; // hash table buckets (a power of two)
    std::uint32_t lanes = 1;     // invocations per particle of the neighbour passes
    std::unique_ptr<PrefixScan> scan;
    gpu::Buffer cellCount, cellStart, hash, rank, sortedToOld;
    gpu::Buffer neighbourMask; // uint[kNeighbourMaskWords] per particle of capacity
    gpu::Buffer collidersNear; // uvec4 per particle of capacity: its substep's collider mask and
                               // its iteration's list
    // The texel views the neighbour passes fetch other particles' data through
    // (NeighbourReadsGlsl.h), one per buffer they read at neighbours' indices; made once, as the
    // buffers never grow. Empty when neighboursAsTexels is false and they read storage blocks.
    struct NeighbourTexels {
        gpu::BufferTexture start, pred[2], pos[2], vel[2], mask, cellStart;
    } neighbourTexels;
    bool neighboursAsTexels = true; // set by compilePasses: every such buffer fits a view
};

} // namespace sluice::rt
