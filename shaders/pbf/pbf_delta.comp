// PBF solve, second half of iteration k (docs/pbf.md 4.2-4.4): the early stop, the position
// correction with s_corr (Macklin & Mueller 2013, eq. 10, 11), collisions and the domain box;
// and in the dispatch that ends the solve, step 5 (velocity, x <- x*, the non-finite guard).
#version 450 core

#define PBF_NEIGHBOUR_PASS 1
#define PBF_WITH_COLLIDERS 1
#define PBF_WITH_BODIES 1
#define PBF_BODY_REACTION collisionReaction
void collisionReaction(uint b, vec3 x, vec3 dx);
#define PBF_SOLID_REACTION addSolidReaction
void addSolidReaction(uint c, vec3 x, vec3 dx);
#include "shared/PbfGlsl.h"
#include "shared/FilmGlsl.h"
#include "shared/BoundaryVolumeGlsl.h"
#include "shared/CollidersNearGlsl.h"

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

#include "shared/BodySumsGlsl.h"

// Adds round(value) to the sum whose positive part starts at word lo (shared/Bodies.h): its
// magnitude to the positive or the negative 64-bit part, the high word only on a carry.
// Integer adds commute, so the total is the same whatever order the particles add in.
void addFixed(uint lo, float value) {
    int v = int(round(clamp(value, -2.0e9, 2.0e9)));
    if (v == 0)
        return;
    uint word = v > 0 ? lo : lo + kBodySumNegative;
    uint magnitude = uint(abs(v));
    uint old = atomicAdd(bodySums[word], magnitude);
    if (old + magnitude < old)
        atomicAdd(bodySums[word + 1u], 1u);
}

// Body b pushed a particle by dx, which ends at x: the body takes the opposite impulse
// -m dx / dt, summed here as dx and (x - c) x dx in fixed point (docs/bodies.md, "Reaction"),
// into its push and moment sums, or with `held` into the held ones (shared/Bodies.h).
void addSums(uint b, bool held, vec3 x, vec3 dx) {
    uint push = held ? kBodySumHeldPush : kBodySumPush;
    uint moment = held ? kBodySumHeldMoment : kBodySumMoment;
    vec3 d = dx * bodies[b].sumScale;
    vec3 m = cross(x - bodies[b].position, dx) * bodies[b].momentScale;
    for (uint axis = 0u; axis < 3u; ++axis)
        addFixed(bodySumWord(b, push, axis), d[axis]);
    for (uint axis = 0u; axis < 3u; ++axis)
        addFixed(bodySumWord(b, moment, axis), m[axis]);
}

// A collider that is no body, its force measured, pushed a particle by dx ending at x: the
// push and its moment about the collider's origin go into its slot of the sums, as a body's
// reaction does (docs/embedding.md, "Forces on colliders"); pbf_collider_forces.comp turns
// them into its force and torque.
void addSolidReaction(uint c, vec3 x, vec3 dx) {
    uint slot = colliders[c].forceSlot;
    vec3 d = dx * (kSumUnitsPerH * P.invH);
    vec3 m = cross(x - colliders[c].forcePoint, dx) * solidMomentScale(c);
    for (uint axis = 0u; axis < 3u; ++axis)
        addFixed(bodySumWord(slot, kBodySumPush, axis), d[axis]);
    for (uint axis = 0u; axis < 3u; ++axis)
        addFixed(bodySumWord(slot, kBodySumMoment, axis), m[axis]);
}

// The pressure pushes li * (share's gradient) each measured static or kinematic collider gave
// the particle at x (the solids' push in main, taken apart by collider).
void measureSolidPushes(vec3 x, float li) {
    uint mask = P.staticColliders, c = 0u;
    while (nextStaticCollider(mask, c)) {
        if (colliders[c].forceSlot == kNoBody)
            continue;
        float share;
        vec3 slope;
        if (colliderBoundaryAt(c, x, share, slope) && allFinite(li * slope))
            addSolidReaction(c, x, li * slope);
    }
}

// Whether this particle is in the water where a body meets a wall or a static collider (within
// h + r of the solid, the body pass's rimBand; tested once, at the first reaction), and that
// solid's normal.
bool rimTested = false;
bool inRim = false;
vec3 rimNormal = vec3(0.0);
vec3 rimX = vec3(0.0); // x*_i, where the test is made

// Body b pushed a particle by dx: the body takes the reaction. A push on the water within the
// rim band of a wall or a static collider (the rim: h + r, with "solids" h + 1.75 spacings) is
// also summed by its direction (docs/bodies.md, "Sealed contacts"): along the solid, its length
// into the rim sum (the pressure beside the body, per area of its sides near the solid); across
// it, into the under sum (what the water between the body and the solid gives; with "solids"
// its moment too, for the film model). The body pass tops the second up to the first.
void addReaction(uint b, vec3 x, vec3 dx) {
    addSums(b, false, x, dx);
    if (!rimTested) {
        rimTested = true;
        inRim = nearestSolidWithin(rimX, rimBand(), rimNormal) < rimBand();
    }
    float len = length(dx);
    if (!inRim || !(len > 0.0))
        return;
    if (abs(dot(dx, rimNormal)) < 0.5 * len) {
        addFixed(bodySumWord(b, kBodySumRim, 0u), len * bodies[b].sumScale);
    } else {
        for (uint axis = 0u; axis < 3u; ++axis)
            addFixed(bodySumWord(b, kBodySumUnder, axis), dx[axis] * bodies[b].sumScale);
        if (P.solidBoundary != 0u) {
            vec3 m = cross(x - bodies[b].position, dx) * bodies[b].momentScale;
            for (uint axis = 0u; axis < 3u; ++axis)
                addFixed(bodySumWord(b, kBodySumUnderMoment, axis), m[axis]);
        }
    }
}

// With "solids", a compressed particle (lambda != 0) records its height in the water column
// over each body it lies under or beside (the film model's level, FilmGlsl.h surfaceWordOf),
// once a substep.
void recordSurface(vec3 x) {
    for (uint b = 0u; b < P.bodyCount; ++b) {
        // Most particles of a column are under its highest: the plain read (possibly stale, so
        // never above the word) skips their atomics; the maximum is the same in any order.
        uint word = surfaceWordOf(b, x);
        uint at = b * kBodySumWords + kBodySumSurface;
        if (word > bodySums[at])
            atomicMax(bodySums[at], word);
    }
}

// The body whose collision push-out (collide) moved this particle in this pass, and the sum of
// those pushes, so that the part of them the domain clamp undoes is taken back (main, at the end).
uint pushedBy = kNoBody;
vec3 pushSum = vec3(0.0);

// A collision push of body b on the particle: the body takes the reaction, and the push is
// remembered.
void collisionReaction(uint b, vec3 x, vec3 dx) {
    addReaction(b, x, dx);
    if (pushedBy == kNoBody || pushedBy == b) {
        pushedBy = b;
        pushSum += dx;
    }
}

// The early stop (docs/pbf.md step 4.2). With the solids' boundary volume ("solids") it ends a
// solve only after an even number of iterations: there the target is met after two or three,
// and water at rest stopped after an odd number keeps stirring ("The early stop's parity").
bool converged(uint k) {
    if (k < P.minIterations || P.targetDensityError <= 0.0 || iterations[k].particles == 0u)
        return false;
    if (P.solidBoundary != 0u && (k & 1u) != 0u)
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

// Each body's boundary volume pushes along its normal with the particle's own lambda (lambda_i
// times the gradient lambda summed); the body takes the reaction.
vec3 pushByBodies(vec3 xi, float li, vec3 x, uvec2 near) {
    uint c;
    while (nextCollider(near, c)) {
        uint b = colliders[c].body;
        if (b == kNoBody)
            continue;
        float phi;
        vec3 normal;
        if (!bodyBoundary(c, xi, phi, normal))
            continue;
        vec3 push = li * boundaryShareSlope(phi) * normal;
        if (!allFinite(push))
            continue;
        x += push;
        addReaction(b, x, push);
    }
    return x;
}

// A particle a body pushes into a wall is put back by the wall (from x to clamped): the body did
// not move it that far. That part of its collision reaction moves to the held sums, of which the
// body pass applies only what stops the body moving into the held particles (docs/bodies.md,
// "Particles held against a wall"): a particle held between a body and the floor carries the
// body as a grain of sand would, and no longer lifts it a little every iteration. The pressure
// push keeps its whole reaction: the wall holding the particle is how the floor carries the
// water's pressure.
void holdAgainstWalls(vec3 x, vec3 clamped) {
    if (pushedBy == kNoBody)
        return;
    vec3 undone = clamped - x;
    vec3 back = sign(undone) * min(abs(undone), abs(pushSum));
    back = mix(vec3(0.0), back, lessThan(pushSum * undone, vec3(0.0)));
    if (any(notEqual(back, vec3(0.0)))) {
        addSums(pushedBy, false, clamped, back);
        addSums(pushedBy, true, clamped, -back);
    }
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
    rimX = xi;
    float li = live ? pred[i].w : 0.0;
    vec3 dp = live ? densityCorrection(i, xi, li) : vec3(0.0);
    dp = pbfLaneSum(vec4(dp, 0.0)).xyz; // every lane's share (uniform: all reach the barriers)
    if (!live || pbfLane != 0u)
        return;
    if (P.solidBoundary != 0u && k == 0u && li != 0.0)
        recordSurface(xi);
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
        if (allFinite(solidPush)) {
            x += solidPush;
            if (P.measuredForces != 0u && P.solidBoundary != 0u)
                measureSolidPushes(xi, li);
        }
        if (P.bodyCount != 0u)
            x = pushByBodies(xi, li, x, visit);
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
