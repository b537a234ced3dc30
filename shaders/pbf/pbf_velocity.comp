// PBF step 5 (docs/pbf.md): velocity from the corrected position, x <- x*, and the non-finite
// guard: a particle whose x* or v is NaN or infinite is put back where it was, at rest, and
// counted, so one bad particle cannot poison its neighbours.
#version 450 core

#include "shared/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindPosIn) buffer PosIn { vec4 pos[]; };
// x* of the last iteration that updated positions (docs/pbf.md step 4): iteration k writes
// pred[k % 2]; with no update at all (a stop at k = 0) the substep's start positions.
layout(std430, binding = kBindPredIn) readonly buffer Pred0 { vec4 pred0[]; };
layout(std430, binding = kBindPredOther) readonly buffer Pred1 { vec4 pred1[]; };
layout(std430, binding = kBindPredStart) readonly buffer PredStart { vec4 predStart[]; };
layout(std430, binding = kBindVelIn) readonly buffer VelIn { vec4 velIn[]; };
layout(std430, binding = kBindVelOut) writeonly buffer VelOut { vec4 velOut[]; };
layout(std430, binding = kBindStats) buffer Stats { PbfStats stats; };

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= PBF_COUNT)
        return;
    vec3 x = pos[i].xyz;
    uint stop = stats.stopIteration;
    uint updates = min(stop, P.maxIterations); // iterations that moved x*
    vec3 xs = updates == 0u         ? predStart[i].xyz
              : (updates & 1u) == 1u ? pred0[i].xyz
                                     : pred1[i].xyz;
    vec3 v = (xs - x) * P.invDt;
    if (!allFinite(xs) || !allFinite(v)) {
        xs = x;
        v = vec3(0.0);
        atomicAdd(stats.nonFinite, 1u);
    }
    if (i == 0u)
        atomicAdd(stats.iterationSum, updates);
    pos[i] = vec4(xs, 0.0);
    velOut[i] = vec4(v, velIn[i].w);
}
