// Exclusive prefix sum of one block of kScanBlock uints in shared memory (Blelloch 1990), in
// the output (which may be the input buffer); the block's total goes to sums[block].
// scan_add.comp then adds the scanned totals. Elements from inputCount on read as 0, and with
// clearInput each input element is zeroed once read (the neighbour grid's counts, ready for
// the next substep's atomics without a clear of their own).
#version 450 core

#include "shared/Pbf.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kScanBlock / 2u) in;

layout(std430, binding = kBindScanInput) buffer Input { uint src[]; };
layout(std430, binding = kBindScanData) writeonly buffer Data { uint data[]; };
layout(std430, binding = kBindScanSums) writeonly buffer Sums { uint sums[]; };

uniform uint count;      // elements in data
uniform uint inputCount; // elements of src read, at most count
uniform uint clearInput; // 1: zero each src element read (src is not data)

shared uint tile[kScanBlock];

void main() {
    uint block = SLUICE_GLOBAL_ID.x / gl_WorkGroupSize.x;
    uint t = gl_LocalInvocationID.x;
    uint base = block * kScanBlock;
    uint a = base + 2u * t, b = a + 1u;
    tile[2u * t] = a < inputCount ? src[a] : 0u;
    tile[2u * t + 1u] = b < inputCount ? src[b] : 0u;
    if (clearInput != 0u) {
        if (a < inputCount)
            src[a] = 0u;
        if (b < inputCount)
            src[b] = 0u;
    }

    uint offset = 1u;
    for (uint d = kScanBlock >> 1u; d > 0u; d >>= 1u) { // up-sweep
        barrier();
        if (t < d) {
            uint ai = offset * (2u * t + 1u) - 1u, bi = offset * (2u * t + 2u) - 1u;
            tile[bi] += tile[ai];
        }
        offset <<= 1u;
    }
    barrier();
    if (t == 0u) {
        sums[block] = tile[kScanBlock - 1u];
        tile[kScanBlock - 1u] = 0u;
    }
    for (uint d = 1u; d < kScanBlock; d <<= 1u) { // down-sweep
        offset >>= 1u;
        barrier();
        if (t < d) {
            uint ai = offset * (2u * t + 1u) - 1u, bi = offset * (2u * t + 2u) - 1u;
            uint x = tile[ai];
            tile[ai] = tile[bi];
            tile[bi] += x;
        }
    }
    barrier();
    if (a < count)
        data[a] = tile[2u * t];
    if (b < count)
        data[b] = tile[2u * t + 1u];
}
