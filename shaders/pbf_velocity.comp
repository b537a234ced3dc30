// PBF step 5 (docs/pbf.md): velocity from the corrected position, x <- x*, and the non-finite
// guard: a particle whose x* or v is NaN or infinite is put back where it was, at rest, and
// counted, so one bad particle cannot poison its neighbours.
#version 450 core

#include "shared/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindPosIn) buffer PosIn { vec4 pos[]; };
layout(std430, binding = kBindPredIn) readonly buffer PredIn { vec4 pred[]; };
layout(std430, binding = kBindVelIn) readonly buffer VelIn { vec4 velIn[]; };
layout(std430, binding = kBindVelOut) writeonly buffer VelOut { vec4 velOut[]; };
layout(std430, binding = kBindStats) buffer Stats { PbfStats stats; };

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= PBF_COUNT)
        return;
    vec3 x = pos[i].xyz;
    vec3 xs = pred[i].xyz;
    vec3 v = (xs - x) * P.step.y;
    if (!allFinite(xs) || !allFinite(v)) {
        xs = x;
        v = vec3(0.0);
        atomicAdd(stats.nonFinite, 1u);
    }
    pos[i] = vec4(xs, 0.0);
    velOut[i] = vec4(v, velIn[i].w);
}
