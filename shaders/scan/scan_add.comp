// Second half of the prefix sum: adds each block's offset to its elements. The offset is the
// block's scanned total, or with reduceTotals the sum of the totals of the blocks before it,
// added up here by the work group (one dispatch fewer than scanning the totals first).
#version 450 core

#include "shared/Pbf.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kScanBlock / 2u) in;

layout(std430, binding = kBindScanData) buffer Data { uint data[]; };
layout(std430, binding = kBindScanSums) readonly buffer Sums { uint sums[]; };

uniform uint count;
uniform uint reduceTotals; // 1: sums holds the blocks' totals, not yet scanned

shared uint partial[kScanBlock / 2u];

// sums[0] + ... + sums[block - 1], by the whole work group (uniform control flow: every
// invocation reaches the barriers).
uint totalsBefore(uint block) {
    uint t = gl_LocalInvocationID.x;
    uint s = 0u;
    for (uint b = t; b < block; b += gl_WorkGroupSize.x)
        s += sums[b];
    partial[t] = s;
    for (uint d = gl_WorkGroupSize.x / 2u; d > 0u; d >>= 1u) {
        barrier();
        if (t < d)
            partial[t] += partial[t + d];
    }
    barrier();
    return partial[0];
}

void main() {
    uint block = SLUICE_GLOBAL_ID.x / gl_WorkGroupSize.x;
    uint add;
    if (reduceTotals != 0u)
        add = totalsBefore(block);
    else
        add = sums[block];
    uint a = block * kScanBlock + 2u * gl_LocalInvocationID.x;
    if (a < count)
        data[a] += add;
    if (a + 1u < count)
        data[a + 1u] += add;
}
