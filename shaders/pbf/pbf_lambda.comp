// PBF solve, first half of iteration k (docs/pbf.md 4.1): density, constraint and lambda
// (Macklin & Mueller 2013, eq. 1, 7, 8), plus the iteration's density-error sum and maximum.
#version 450 core

#define PBF_NEIGHBOUR_PASS 1
#define PBF_WITH_COLLIDERS 1
#define PBF_WITH_BODIES 1
#include "glsl/PbfGlsl.h"
#include "glsl/BoundaryVolumeGlsl.h"
#include "glsl/CollidersNearGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

uniform uint iteration; // k, the solver iteration of this dispatch

// x* (xyz); lambda writes its lambda_i into w, for pbf_delta.comp (one read per neighbour).
layout(std430, binding = kBindPredIn) buffer PredIn { vec4 pred[]; };
layout(std430, binding = kBindPredStart) readonly buffer PredStart { vec4 predStart[]; };
layout(std430, binding = kBindCellStart) readonly buffer CellStart { uint cellStart[]; };
layout(std430, binding = kBindNeighbourMask) buffer Mask { uint neighbourMask[]; };
layout(std430, binding = kBindVelIn) buffer VelIn { vec4 vel[]; };
layout(std430, binding = kBindStats) buffer Stats {
    PbfStats stats;
    PbfIterationStats iterations[];
};

shared float groupSum[kPbfLocalSize];
shared float groupMax[kPbfLocalSize];

// One neighbour's share of the density and of the constraint's gradient (eq. 1, 8).
void addNeighbour(vec3 d, float q2, inout float density, inout vec3 gradSum, inout float gradSq) {
    density += poly6(q2);
    vec3 g = PBF_VOLUME * spikyGrad(d, q2);
    gradSum += g;
    gradSq += dot(g, g);
}

// Iteration 0 (x* = the start positions): the full search over the candidates, which also
// records N(i) as the mask every later neighbour pass of the substep reads (docs/pbf.md step
// 3). This lane visits the candidates of its mask words (w % PBF_LANES == pbfLane) in increasing
// order, so each of its words is complete when its next one begins, and writes only those words.
// Returns the neighbours this lane found.
uint searchAndRecord(uint i, vec3 xi, inout float density, inout vec3 gradSum,
                     inout float gradSq) {
    uint maskBase = i * kNeighbourMaskWords;
    uint word = pbfLane, bits = 0u, neighbours = 0u;
    PBF_RANGES_BEGIN(predStart, i)
        uint stop_ = pbfBase_ + (end_ - begin_);
        for (uint w = pbfBase_ >> 5u; w < ((stop_ + 31u) >> 5u); ++w) {
            PBF_SKIP_OTHER_LANES(w)
            uint hi = min(stop_, (w + 1u) << 5u);
            for (uint c = max(pbfBase_, w << 5u); c < hi; ++c) {
                if (c < kNeighbourMaskBits && w != word) {
                    neighbourMask[maskBase + word] = bits;
                    word = w;
                    bits = 0u;
                }
                uint j = begin_ + (c - pbfBase_);
                vec3 xj = PBF_POS_AT(pred, j).xyz;
                if (!pbfIsNeighbour(xi, xj, i, j, pbfDense_, cc_))
                    continue;
                if (c < kNeighbourMaskBits)
                    bits |= 1u << (c & 31u);
                ++neighbours;
                vec3 d = xi - xj;
                addNeighbour(d, dot(d, d), density, gradSum, gradSq);
            }
        }
    PBF_RANGES_END
    uint candidates = pbfBase_;
    // This lane's words after its last candidate: the one being filled, then zeros.
    for (; word < kNeighbourMaskWords; word += kPbfLanes) {
        neighbourMask[maskBase + word] = bits;
        bits = 0u;
    }
    if (pbfLane == 0u) {
        if (candidates > kNeighbourMaskBits)
            atomicAdd(stats.maskOverflow, 1u);
        atomicMax(stats.maxCandidates, candidates);
    }
    return neighbours;
}

// Each dynamic body's boundary volume at particle i, at xi in iteration k, added to `boundary`
// and its slope to `gradient`: the bodies of the colliders near the particle, whose mask
// iteration 0 takes from the substep start and keeps (a scene without bodies has none), or
// in a later iteration the list the previous delta pass handed on. What is left of it after the
// bodies out of reach from xi is the list of this iteration's delta pass (CollidersNearGlsl.h).
void addBodyBoundary(uint i, uint k, vec3 xi, inout float boundary, inout vec3 gradient) {
    if (P.bodyCount == 0u)
        return;
    uvec2 near = k == 0u ? collidersWithinReach(xi) : collidersNear[i].zw;
    uvec2 reach = near, kept = near;
    uint solid;
    while (nextCollider(near, solid)) {
        if (colliders[solid].body == kNoBody)
            continue;
        float phi;
        vec3 normal;
        if (bodyBoundary(solid, xi, phi, normal)) {
            boundary += boundaryShare(phi);
            gradient += boundaryShareSlope(phi) * normal;
        }
        if (!bodyMayReach(solid, xi, phi))
            kept[solid >> 5u] &= ~(1u << (solid & 31u));
    }
    if (k == 0u)
        collidersNear[i] = uvec4(reach, kept);
    else
        collidersNear[i].zw = kept;
}

void main() {
    uint k = iteration;
    // An earlier iteration met the target: nothing more to do this substep. The same for the
    // whole dispatch, so returning before the barriers is uniform.
    if (stats.stopIteration < k)
        return;

    uint i = PBF_PARTICLE;
    pbfLane = PBF_LANE;
    if (SLUICE_GLOBAL_ID.x == 0u)
        atomicAdd(stats.solveDispatches, 1u); // this dispatch ran (--bench counts them)
    bool live = i < PBF_LIVE;
    vec3 xi = live ? pred[i].xyz : vec3(0.0);
    float density = pbfLane == 0u ? poly6(0.0) : 0.0; // the particle itself
    vec3 gradSum = vec3(0.0);
    float gradSq = 0.0;
    float neighbours = 0.0;
    if (live) {
        if (k == 0u) {
            neighbours = float(searchAndRecord(i, xi, density, gradSum, gradSq));
        } else {
            PBF_NEIGHBOURS_BEGIN(predStart, neighbourMask, pred, i, xi)
                addNeighbour(d, q2, density, gradSum, gradSq);
            PBF_NEIGHBOURS_END
        }
    }
    // Every lane's share (uniform: all invocations reach the barriers).
    vec4 sums = pbfLaneSum(vec4(gradSum, gradSq));
    vec2 counted = pbfLaneSum(vec4(density, neighbours, 0.0, 0.0)).xy;

    float c = 0.0;
    if (live && pbfLane == 0u) {
        gradSum = sums.xyz;
        gradSq = sums.w;
        density = counted.x;
        if (k == 0u)
            atomicMax(stats.maxNeighbours, uint(counted.y));
        // Solids fill part of the support (docs/pbf.md, "Boundary volume"): the walls', the
        // static colliders' and each dynamic body's boundary volume adds to the density, and
        // the particle's own gradient gains its slope.
        float boundary = 0.0;
        addWallBoundary(xi, boundary, gradSum);
        addColliderBoundary(xi, boundary, gradSum);
        addBodyBoundary(i, k, xi, boundary, gradSum);
        c = max(PBF_VOLUME * density + boundary - 1.0, 0.0); // rho / rho0 - 1, compression only
        pred[i].w = -c / (gradSq + dot(gradSum, gradSum) + P.epsilon);
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
        const uint perGroup = kPbfLocalSize / kPbfLanes;
        uint first = (SLUICE_GLOBAL_ID.x - t) / kPbfLanes; // this group's first particle
        uint live = PBF_LIVE > first ? min(PBF_LIVE - first, perGroup) : 0u;
        atomicAdd(iterations[k].particles, live);
    }
}
