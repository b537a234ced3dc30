// Counting sort, scatter half: every particle claims slot start[bucket] + rank.
#version 450 core

#include "glsl/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindCellStart) readonly buffer CellStart { uint cellStart[]; };
layout(std430, binding = kBindHash) readonly buffer Hash { uint hash[]; };
layout(std430, binding = kBindRank) readonly buffer Rank { uint rank[]; };
layout(std430, binding = kBindSortedToOld) writeonly buffer SortedToOld { uint sortedToOld[]; };

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= PBF_COUNT)
        return;
    sortedToOld[cellStart[hash[i]] + rank[i]] = i;
}
