// Gathers x, v, x* and ids into sorted order, so a cell's particles sit together in memory
// (the paper's linked lists scattered them). With PBF_SCATTER_REORDER it is the counting
// sort's scatter too: each source particle writes its data straight to its slot
// cellStart[bucket] + rank, the same permutation without the sortedToOld round trip (one
// dispatch and barrier fewer; not for --deterministic, whose bucket sort reorders the slots
// between the two).
#version 450 core

#include "glsl/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindHash) readonly buffer Hash { uint hash[]; };
#ifdef PBF_SCATTER_REORDER
layout(std430, binding = kBindCellStart) readonly buffer CellStart { uint cellStart[]; };
layout(std430, binding = kBindRank) readonly buffer Rank { uint rank[]; };
#else
layout(std430, binding = kBindSortedToOld) readonly buffer SortedToOld { uint sortedToOld[]; };
#endif
layout(std430, binding = kBindPosIn) readonly buffer PosIn { vec4 posIn[]; };
layout(std430, binding = kBindPosOut) writeonly buffer PosOut { vec4 posOut[]; };
layout(std430, binding = kBindVelIn) readonly buffer VelIn { vec4 velIn[]; };
layout(std430, binding = kBindVelOut) writeonly buffer VelOut { vec4 velOut[]; };
layout(std430, binding = kBindPredIn) readonly buffer PredIn { vec4 predIn[]; };
layout(std430, binding = kBindPredOut) writeonly buffer PredOut { vec4 predOut[]; };
layout(std430, binding = kBindIdIn) readonly buffer IdIn { uint idIn[]; };
layout(std430, binding = kBindIdOut) writeonly buffer IdOut { uint idOut[]; };

void main() {
#ifdef PBF_SCATTER_REORDER
    uint o = SLUICE_GLOBAL_ID.x;
    if (o >= PBF_COUNT)
        return;
    uint k = cellStart[hash[o]] + rank[o];
#else
    uint k = SLUICE_GLOBAL_ID.x;
    if (k >= PBF_COUNT)
        return;
    uint o = sortedToOld[k];
#endif
    // A removed particle (in the bucket after the last) is marked w = 1 until it is compacted
    // away, so every later pass and substep knows it.
    posOut[k] = hash[o] == P.activeBuckets ? vec4(posIn[o].xyz, 1.0) : posIn[o];
    velOut[k] = velIn[o];
    predOut[k] = predIn[o];
    idOut[k] = idIn[o];
}
