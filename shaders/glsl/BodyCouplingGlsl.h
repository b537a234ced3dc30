// The body coupling in the solve's delta pass (docs/bodies.md, "Reaction"): what the
// dynamic bodies and the measured colliders take from one particle's corrections. The fluid's
// pass (pbf_delta.comp) computes the fluid; it calls this part at four points of main, and
// this part alone writes the reaction sums (shared/Bodies.h):
//   1. startCoupling(x*_i)           before anything moves the particle;
//   2. couplePressure(...)           the bodies' and the measured solids' pressure pushes;
//   3. collisionReaction (by collide) each body's collision push-out, through
//                                    PBF_BODY_REACTION;
//   4. holdAgainstWalls(x, clamped)  the part of those push-outs the domain's walls undid.
// Include after glsl/PbfGlsl.h, glsl/FilmGlsl.h, glsl/BoundaryVolumeGlsl.h,
// glsl/CollidersNearGlsl.h and the `bodySums` buffer with glsl/BodySumsGlsl.h.
#ifndef SLUICE_SHARED_BODY_COUPLING_GLSL_H
#define SLUICE_SHARED_BODY_COUPLING_GLSL_H

// One particle's coupling state through one delta pass (one invocation's, in gCoupling).
struct BodyCoupling {
    vec3 x;         // x*_i, where the rim test is made
    bool rimTested; // the rim test made (at the first reaction: most particles meet no body)
    bool inRim;     // x lies within the rim band of a wall or a static collider
    vec3 rimNormal; // that solid's normal
    uint pushedBy;  // the body whose collision push-out moved the particle, or kNoBody
    vec3 pushSum;   // the sum of that body's push-outs
};

BodyCoupling gCoupling;

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

// Adds vector v to the sum of `slot` (a body, or a measured collider's slot) at word `sum`.
void addFixedVec(uint slot, uint sum, vec3 v) {
    for (uint axis = 0u; axis < 3u; ++axis)
        addFixed(bodySumWord(slot, sum, axis), v[axis]);
}

// Body b pushed a particle by dx, which ends at x: the body takes the opposite impulse
// -m dx / dt, summed here as dx and (x - c) x dx in fixed point (docs/bodies.md, "Reaction"),
// into its push and moment sums, or with `held` into the held ones (shared/Bodies.h).
void addSums(uint b, bool held, vec3 x, vec3 dx) {
    addFixedVec(b, held ? kBodySumHeldPush : kBodySumPush, dx * bodies[b].sumScale);
    addFixedVec(b, held ? kBodySumHeldMoment : kBodySumMoment,
                cross(x - bodies[b].position, dx) * bodies[b].momentScale);
}

// A collider that is no body, its force measured, pushed a particle by dx ending at x: the
// push and its moment about the collider's forcePoint go into its slot of the sums, as a
// body's reaction does (docs/embedding.md, "Forces on colliders"); pbf_collider_forces.comp
// turns them into its force and torque.
void addSolidReaction(uint c, vec3 x, vec3 dx) {
    uint slot = colliders[c].forceSlot;
    addFixedVec(slot, kBodySumPush, dx * (kSumUnitsPerH * P.invH));
    addFixedVec(slot, kBodySumMoment, cross(x - colliders[c].forcePoint, dx) * solidMomentScale(c));
}

// The pressure pushes li * (share's gradient) each measured static or kinematic collider gave
// the particle at x (the solids' push in the delta pass, taken apart by collider).
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

// Body b pushed a particle by dx: the body takes the reaction. A push on the water within the
// rim band of a wall or a static collider (h + 1.75 spacings) mostly across the solid (within
// 60 degrees of its normal) is also summed, with its moment, into the under sums: what the water
// between the body and the solid gives, which the film model holds to the pressure of the water
// over the body (docs/bodies.md, "The film under a body").
void addReaction(uint b, vec3 x, vec3 dx) {
    addSums(b, false, x, dx);
    if (!gCoupling.rimTested) {
        gCoupling.rimTested = true;
        gCoupling.inRim =
            nearestSolidWithin(gCoupling.x, rimBand(), gCoupling.rimNormal) < rimBand();
    }
    float len = length(dx);
    if (!gCoupling.inRim || !(abs(dot(dx, gCoupling.rimNormal)) >= 0.5 * len) || !(len > 0.0))
        return;
    addFixedVec(b, kBodySumUnder, dx * bodies[b].sumScale);
    addFixedVec(b, kBodySumUnderMoment, cross(x - bodies[b].position, dx) * bodies[b].momentScale);
}

// A compressed particle (lambda != 0) records its height in the water column over each body it
// lies under or beside (the film model's level, FilmGlsl.h surfaceWordOf), once a substep.
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

// 1. The particle's coupling starts at x*_i in iteration k, its lambda li: in the first
// iteration a compressed particle records the film model's level.
void startCoupling(vec3 xi, uint k, float li) {
    gCoupling = BodyCoupling(xi, false, false, vec3(0.0), kNoBody, vec3(0.0));
    if (k == 0u && li != 0.0)
        recordSurface(xi);
}

// 2. The pressure pushes of the bodies and the measured solids on a compressed particle at x*_i
// (li != 0), which has moved to x: each body's boundary volume pushes along its normal with the
// particle's own lambda (lambda_i times the gradient of its share), and the body takes the
// reaction; the measured static and kinematic colliders' pushes are summed for their forces
// when the solids' push was finite (`measure`). Returns where the bodies' pushes leave the
// particle.
vec3 couplePressure(vec3 xi, float li, vec3 x, uvec2 near, bool measure) {
    if (measure && P.measuredForces != 0u)
        measureSolidPushes(xi, li);
    if (P.bodyCount == 0u)
        return x;
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

// 3. A collision push-out of body b on the particle (collide calls it): the body takes the
// reaction, and the push is remembered for holdAgainstWalls.
void collisionReaction(uint b, vec3 x, vec3 dx) {
    addReaction(b, x, dx);
    if (gCoupling.pushedBy == kNoBody || gCoupling.pushedBy == b) {
        gCoupling.pushedBy = b;
        gCoupling.pushSum += dx;
    }
}

// 4. A particle a body pushes into a wall is put back by the wall (from x to clamped): the body
// did not move it that far. That part of its collision reaction moves to the held sums, of
// which the body pass applies only what stops the body moving into the held particles
// (docs/bodies.md, "Particles held against a wall"): a particle held between a body and the
// floor carries the body as a grain of sand would, and no longer lifts it a little every
// iteration. The pressure push keeps its whole reaction: the wall holding the particle is how
// the floor carries the water's pressure.
void holdAgainstWalls(vec3 x, vec3 clamped) {
    uint b = gCoupling.pushedBy;
    if (b == kNoBody)
        return;
    vec3 undone = clamped - x;
    vec3 back = sign(undone) * min(abs(undone), abs(gCoupling.pushSum));
    back = mix(vec3(0.0), back, lessThan(gCoupling.pushSum * undone, vec3(0.0)));
    if (any(notEqual(back, vec3(0.0)))) {
        addSums(b, false, clamped, back);
        addSums(b, true, clamped, -back);
    }
}

#endif // SLUICE_SHARED_BODY_COUPLING_GLSL_H
