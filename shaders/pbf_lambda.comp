// PBF solve, first half of iteration k (docs/pbf.md 4.1): density, constraint and lambda
// (Macklin & Mueller 2013, eq. 1, 7, 8), plus the iteration's density-error sum and maximum.
#version 450 core

#include "shared/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

uniform uint iteration; // k, the solver iteration of this dispatch

layout(std430, binding = kBindPredIn) readonly buffer PredIn { vec4 pred[]; };
layout(std430, binding = kBindLambda) writeonly buffer Lambda { float lambda[]; };
layout(std430, binding = kBindPredStart) readonly buffer PredStart { vec4 predStart[]; };
layout(std430, binding = kBindCellCount) readonly buffer CellCount { uint cellCount[]; };
layout(std430, binding = kBindCellStart) readonly buffer CellStart { uint cellStart[]; };
layout(std430, binding = kBindNeighbourMask) readonly buffer Mask { uint neighbourMask[]; };
layout(std430, binding = kBindVelIn) buffer VelIn { vec4 vel[]; };
layout(std430, binding = kBindStats) buffer Stats {
    PbfStats stats;
    PbfIterationStats iterations[];
};

shared float groupSum[kPbfLocalSize];
shared float groupMax[kPbfLocalSize];

void main() {
    uint k = iteration;
    // An earlier iteration met the target: nothing more to do this substep. The same for the
    // whole dispatch, so returning before the barriers is uniform.
    if (stats.stopIteration < k)
        return;

    uint i = SLUICE_GLOBAL_ID.x;
    float c = 0.0;
    if (i < PBF_COUNT) {
        vec3 xi = pred[i].xyz;
        float density = poly6(0.0); // the particle itself
        vec3 gradSum = vec3(0.0);
        float gradSq = 0.0;
        PBF_NEIGHBOURS_BEGIN(predStart, neighbourMask, pred, i, xi)
            density += poly6(q2);
            vec3 g = PBF_VOLUME * spikyGrad(d, q2);
            gradSum += g;
            gradSq += dot(g, g);
        PBF_NEIGHBOURS_END
        c = max(PBF_VOLUME * density - 1.0, 0.0); // rho / rho0 - 1, compression only
        lambda[i] = -c / (gradSq + dot(gradSum, gradSum) + P.epsilon);
        vel[i].w = c; // kept for the statistics and for colouring by density error
    }

    // Work-group sum and max in a fixed tree order, then integer atomics: the total is the
    // same whatever order the groups finish in.
    uint t = gl_LocalInvocationID.x;
    groupSum[t] = c;
    groupMax[t] = c;
    for (uint s = kPbfLocalSize / 2u; s > 0u; s >>= 1u) {
        barrier();
        if (t < s) {
            groupSum[t] += groupSum[t + s];
            groupMax[t] = max(groupMax[t], groupMax[t + s]);
        }
    }
    if (t == 0u) {
        uint fixedSum = uint(min(groupSum[0] * kErrorFixedScale, 4.0e9));
        uint old = atomicAdd(iterations[k].errorLo, fixedSum);
        if (old + fixedSum < old)
            atomicAdd(iterations[k].errorHi, 1u);
        atomicMax(iterations[k].errorMaxBits, floatBitsToUint(groupMax[0]));
        uint first = SLUICE_GLOBAL_ID.x - t; // this group's first particle
        uint live = PBF_COUNT > first ? min(PBF_COUNT - first, kPbfLocalSize) : 0u;
        atomicAdd(iterations[k].particles, live);
    }
}
