// Second half of the prefix sum: adds each block's scanned offset to its elements.
#version 450 core

#include "shared/Pbf.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kScanBlock / 2u) in;

layout(std430, binding = kBindScanData) buffer Data { uint data[]; };
layout(std430, binding = kBindScanSums) readonly buffer Sums { uint sums[]; };

uniform uint count;

void main() {
    uint block = SLUICE_GLOBAL_ID.x / gl_WorkGroupSize.x;
    uint add = sums[block];
    uint a = block * kScanBlock + 2u * gl_LocalInvocationID.x;
    if (a < count)
        data[a] += add;
    if (a + 1u < count)
        data[a + 1u] += add;
}
