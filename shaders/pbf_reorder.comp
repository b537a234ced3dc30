// Gathers x, v, x* and ids into sorted order, so a cell's particles sit together in memory
// (the paper's linked lists scattered them).
#version 450 core

#include "shared/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindSortedToOld) readonly buffer SortedToOld { uint sortedToOld[]; };
layout(std430, binding = kBindPosIn) readonly buffer PosIn { vec4 posIn[]; };
layout(std430, binding = kBindPosOut) writeonly buffer PosOut { vec4 posOut[]; };
layout(std430, binding = kBindVelIn) readonly buffer VelIn { vec4 velIn[]; };
layout(std430, binding = kBindVelOut) writeonly buffer VelOut { vec4 velOut[]; };
layout(std430, binding = kBindPredIn) readonly buffer PredIn { vec4 predIn[]; };
layout(std430, binding = kBindPredOut) writeonly buffer PredOut { vec4 predOut[]; };
layout(std430, binding = kBindIdIn) readonly buffer IdIn { uint idIn[]; };
layout(std430, binding = kBindIdOut) writeonly buffer IdOut { uint idOut[]; };

void main() {
    uint k = SLUICE_GLOBAL_ID.x;
    if (k >= PBF_COUNT)
        return;
    uint o = sortedToOld[k];
    posOut[k] = posIn[o];
    velOut[k] = velIn[o];
    predOut[k] = predIn[o];
    idOut[k] = idIn[o];
}
