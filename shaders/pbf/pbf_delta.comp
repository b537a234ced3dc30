// PBF solve, second half of iteration k (docs/pbf.md 4.2-4.4): the early stop, the position
// correction with s_corr (Macklin & Mueller 2013, eq. 10, 11), collisions and the domain box;
// and in the dispatch that ends the solve, step 5 (velocity, x <- x*, the non-finite guard).
// What the bodies and the measured colliders take from the corrections is the body coupling's
// (glsl/BodyCouplingGlsl.h), called at its four numbered points.
#version 450 core

#define PBF_NEIGHBOUR_PASS 1
#define PBF_WITH_COLLIDERS 1
#define PBF_WITH_BODIES 1
#define PBF_BODY_REACTION collisionReaction
void collisionReaction(uint b, vec3 x, vec3 dx);
#define PBF_SOLID_REACTION addSolidReaction
void addSolidReaction(uint c, vec3 x, vec3 dx);
#include "glsl/PbfGlsl.h"
#include "glsl/FilmGlsl.h"
#include "glsl/BoundaryVolumeGlsl.h"
#include "glsl/CollidersNearGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

uniform uint iteration; // k, the solver iteration of this dispatch

layout(std430, binding = kBindPosIn) buffer PosIn { vec4 pos[]; };
layout(std430, binding = kBindVelIn) readonly buffer VelIn { vec4 velIn[]; };
layout(std430, binding = kBindVelOut) writeonly buffer VelOut { vec4 velOut[]; };
layout(std430, binding = kBindPredIn) readonly buffer PredIn { vec4 pred[]; };
layout(std430, binding = kBindPredOut) writeonly buffer PredOut { vec4 predOut[]; };
layout(std430, binding = kBindPredStart) readonly buffer PredStart { vec4 predStart[]; };
layout(std430, binding = kBindCellStart) readonly buffer CellStart { uint cellStart[]; };
layout(std430, binding = kBindNeighbourMask) readonly buffer Mask { uint neighbourMask[]; };
layout(std430, binding = kBindStats) buffer Stats {
    PbfStats stats;
    PbfIterationStats iterations[];
};
layout(std430, binding = kBindSolveArgs) writeonly buffer SolveArgs { PbfDispatchArgs args[]; };
layout(std430, binding = kBindBodySums) buffer BodySums { uint bodySums[]; };

#include "glsl/BodySumsGlsl.h"
#include "glsl/BodyCouplingGlsl.h"

// The early stop (docs/pbf.md step 4.2). It ends a solve only after an even number of
// iterations: the target is met after two or three, and water at rest stopped after an odd
// number keeps stirring ("The early stop's parity").
bool converged(uint k) {
    if (k < P.minIterations || P.targetDensityError <= 0.0 || iterations[k].particles == 0u)
        return false;
    if ((k & 1u) != 0u)
        return false;
    float sum = (float(iterations[k].errorHi) * 4294967296.0 + float(iterations[k].errorLo)) /
                kErrorFixedScale;
    return sum / float(iterations[k].particles) <= P.targetDensityError;
}

// Iteration k met the target: no update in it (x* stays its input), and the later iterations'
// lambda and delta dispatches launch no group.
void stopAt(uint k) {
    if (gl_LocalInvocationIndex == 0u)
        atomicMin(stats.stopIteration, k);
    if (SLUICE_GLOBAL_ID.x == 0u)
        for (uint a = (k + 1u) * P.solveChunks; a < P.maxIterations * P.solveChunks; ++a)
            args[a].groupsX = 0u;
}

// This lane's share of dp_i / V (eq. 12 with s_corr, eq. 13). s_corr's (W / W(delta q))^n:
// pow() is exp2(n log2 w) on llvmpipe, two polynomial approximations per neighbour. An integer
// n in [1, 7] (the default is 4) is a product of w, w^2 and w^4 instead, the same to float
// rounding. The test is outside the loop so the loop holds one form only.
vec3 densityCorrection(uint i, vec3 xi, float li) {
    float scorrScale = -P.scorrK * P.lambdaRef;
    vec3 dp = vec3(0.0);
    uint n = uint(P.scorrN);
    if (float(n) == P.scorrN && n >= 1u && n <= 7u) {
        bool odd = (n & 1u) != 0u, two = (n & 2u) != 0u, four = (n & 4u) != 0u;
        PBF_NEIGHBOURS_BEGIN(predStart, neighbourMask, pred, i, xi)
            float w = poly6(q2) * P.invWDeltaQ;
            float w2 = w * w;
            float wn = (odd ? w : 1.0) * (two ? w2 : 1.0) * (four ? w2 * w2 : 1.0);
            float scorr = scorrScale * wn;
            dp += (li + pj.w + scorr) * spikyGrad(d, q2);
        PBF_NEIGHBOURS_END
    } else {
        PBF_NEIGHBOURS_BEGIN(predStart, neighbourMask, pred, i, xi)
            float scorr = scorrScale * pow(poly6(q2) * P.invWDeltaQ, P.scorrN);
            dp += (li + pj.w + scorr) * spikyGrad(d, q2);
        PBF_NEIGHBOURS_END
    }
    return dp;
}

// PBF step 5 (docs/pbf.md) for particle i, whose x* the solve ends with after `updates`
// iterations that moved it: velocity from the correction, x <- x*, and the non-finite guard (a
// particle whose x* or v is NaN or infinite is put back where it was, at rest, and counted, so
// one bad particle cannot poison its neighbours). Only particle i's own x is read and written
// here, and no later solve pass reads x: the dispatch that meets the target or runs the last
// iteration does this instead of a pass of its own.
void endSolve(uint i, vec3 xs, uint updates) {
    vec3 x = pos[i].xyz;
    vec3 v = (xs - x) * P.invDt;
    if (!allFinite(xs) || !allFinite(v)) {
        xs = x;
        v = vec3(0.0);
        atomicAdd(stats.nonFinite, 1u);
    }
    if (SLUICE_GLOBAL_ID.x == 0u)
        atomicAdd(stats.iterationSum, updates);
    pos[i] = vec4(xs, 0.0);
    velOut[i] = vec4(v, velIn[i].w);
}

void main() {
    uint k = iteration;
    uint i = PBF_PARTICLE;
    pbfLane = PBF_LANE;
    if (stats.stopIteration < k)
        return; // a guard: after the stop this dispatch launches no work group
    if (SLUICE_GLOBAL_ID.x == 0u)
        atomicAdd(stats.solveDispatches, 1u); // this dispatch ran (--bench counts them)
    if (converged(k)) {
        stopAt(k);
        if (i < PBF_LIVE && pbfLane == 0u)
            endSolve(i, pred[i].xyz, k);
        return;
    }
    bool live = i < PBF_LIVE;
#if PBF_LANES == 1
    if (!live)
        return; // one lane: no barriers below
#endif
    vec3 xi = live ? pred[i].xyz : vec3(0.0);
    float li = live ? pred[i].w : 0.0;
    vec3 dp = live ? densityCorrection(i, xi, li) : vec3(0.0);
    dp = pbfLaneSum(vec4(dp, 0.0)).xyz; // every lane's share (uniform: all reach the barriers)
    if (!live || pbfLane != 0u)
        return;
    startCoupling(xi, k, li);
    // A non-finite correction is dropped before collide and clamp (GLSL min/max/clamp may turn
    // NaN into a finite corner), so it cannot reach the neighbours in the next iteration;
    // endSolve counts what still goes wrong.
    vec3 x = xi + PBF_VOLUME * dp;
    vec3 x0 = predStart[i].xyz; // where the substep's collider mask was taken
    if (!allFinite(x))
        x = xi;
    // The colliders this iteration's lambda pass left near x* (all of them without bodies).
    uvec2 visit = P.bodyCount != 0u ? collidersNear[i].zw : allColliders();
    // The walls and static colliders push along their boundary volume's gradient with the
    // particle's own lambda, as a body does (without a reaction: they do not move). A particle
    // that is not compressed has lambda 0: no solid pushes it, so their fields are not sampled.
    if (li != 0.0) {
        float share = 0.0;
        vec3 slope = vec3(0.0);
        addWallBoundary(xi, share, slope);
        addColliderBoundary(xi, share, slope);
        vec3 solidPush = li * slope;
        bool finitePush = allFinite(solidPush);
        if (finitePush)
            x += solidPush;
        x = couplePressure(xi, li, x, visit, finitePush);
    }
    if (!allFinite(x))
        x = xi;
    x = collide(x, pos[i].xyz, withinStepMargin(x, xi) ? visit : collidersNearNow(i, x, x0));
    if (!allFinite(x))
        x = xi;
    vec3 clamped = clampToDomain(x);
    holdAgainstWalls(x, clamped);
    predOut[i] = vec4(clamped, 0.0);
    // The next iteration's lambda starts from this list while the particle stays near x*.
    if (P.bodyCount != 0u && !withinStepMargin(clamped, xi))
        collidersNear[i].zw = collidersNearNow(i, clamped, x0);
    if (k + 1u == P.maxIterations)
        endSolve(i, clamped, P.maxIterations);
}
