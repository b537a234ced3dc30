// Deterministic mode: orders each bucket's slots by source index, undoing the scheduling order
// the counting atomics left. Buckets hold a handful of particles, so insertion sort.
#version 450 core

#include "glsl/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindCellStart) readonly buffer CellStart { uint cellStart[]; };
layout(std430, binding = kBindSortedToOld) buffer SortedToOld { uint sortedToOld[]; };

void main() {
    uint b = SLUICE_GLOBAL_ID.x;
    if (b >= P.activeBuckets)
        return;
    uint s = cellStart[b];
    uint n = cellStart[b + 1u] - s;
    if (n < 2u)
        return;
    for (uint a = 1u; a < n; ++a) {
        uint key = sortedToOld[s + a];
        uint k = a;
        while (k > 0u && sortedToOld[s + k - 1u] > key) {
            sortedToOld[s + k] = sortedToOld[s + k - 1u];
            --k;
        }
        sortedToOld[s + k] = key;
    }
}
