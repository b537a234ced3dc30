// GLSL only: the colliders near each particle of a substep (docs/bodies.md, "Bodies near a
// particle"), for the solve's passes. Include it after glsl/PbfGlsl.h with PBF_WITH_BODIES and
// PBF_WITH_COLLIDERS (it reads the body and collider records and the parameter block).
#ifndef SLUICE_SHARED_COLLIDERS_NEAR_GLSL_H
#define SLUICE_SHARED_COLLIDERS_NEAR_GLSL_H

#ifndef __cplusplus

// The colliders that may reach a particle during its substep's solve, bit c of uvec2 word
// c / 32 (at most 64 colliders): every static and kinematic collider, and each body whose
// bounding sphere lies within h + r + PBF_NEAR_MARGIN of the particle's substep start. Lambda
// of iteration 0 writes it (.xy); every later use first checks that the particle is still
// within PBF_NEAR_MARGIN of its start, so a body its kernel or radius reaches now is always in
// it, and visiting its bits in order gives the same sums, in the same order, as the loop over
// all colliders (docs/bodies.md, "Bodies near a particle"). With 64 crates that loop was most
// of the solve on llvmpipe.
//
// .zw is the iteration's list, a subset of .xy: lambda of every iteration drops the bodies it
// finds too far from x* (none of their kernel or push-out can reach the particle before it moves
// PBF_STEP_MARGIN; bodyMayReach), and delta of the same iteration visits only those left, at
// the same x* for the pressure push and, when the corrected position is within the margin of x*,
// for the push-out. Delta then hands the list to the next iteration's lambda, or the substep's
// mask when the particle moved farther (docs/bodies.md, "Bodies near a particle").
layout(std430, binding = kBindCollidersNear) buffer CollidersNearBuf { uvec4 collidersNear[]; };
#define PBF_NEAR_MARGIN PBF_H
#define PBF_STEP_MARGIN (PBF_H / 16.0)

// Every collider of the scene (at most 64), as a mask.
uvec2 allColliders() {
    uint n = P.colliderCount;
    return uvec2(n >= 32u ? 0xffffffffu : (1u << n) - 1u,
                 n >= 64u ? 0xffffffffu : (n > 32u ? (1u << (n - 32u)) - 1u : 0u));
}

// The mask for a particle starting its substep at x0 (lambda of iteration 0 stores it).
uvec2 collidersWithinReach(vec3 x0) {
    uvec2 near = uvec2(0u);
    for (uint c = 0u; c < P.colliderCount; ++c) {
        if (colliders[c].body == kNoBody || !bodyOutOfReach(c, x0, PBF_RADIUS + PBF_NEAR_MARGIN))
            near[c >> 5u] |= 1u << (c & 31u);
    }
    return near;
}

// The stored mask of particle i, now at x after starting at x0; every collider if it moved
// farther than the margin, or if the scene has no body (and so no mask: its buffer is one entry).
uvec2 collidersNearNow(uint i, vec3 x, vec3 x0) {
    if (P.bodyCount == 0u)
        return allColliders();
    vec3 moved = x - x0;
    return dot(moved, moved) < PBF_NEAR_MARGIN * PBF_NEAR_MARGIN ? collidersNear[i].xy
                                                                 : allColliders();
}

// Whether collider c's body may still reach a particle at x* = x before it moves
// PBF_STEP_MARGIN from there: its collision's bounding-sphere test (bodyOutOfReach with r) could
// pass, and, where bodyBoundary sampled its field (phi with the surface offset, else
// kPhiNotSampled), phi is under h plus three margins. A trilinear field changes by at most
// sqrt(3) per unit of motion inside its grid box and by 1 more outside it, so a body left out
// has phi >= h (no boundary volume, no pressure push) and phi > r (no push-out) anywhere within
// the margin.
bool bodyMayReach(uint c, vec3 x, float phi) {
    if (bodyOutOfReach(c, x, PBF_RADIUS + PBF_STEP_MARGIN))
        return false;
    return phi == kPhiNotSampled || phi < PBF_H + 3.0 * PBF_STEP_MARGIN;
}

// Whether a particle moved from x* = xi to x stays within PBF_STEP_MARGIN, where the
// iteration's list holds.
bool withinStepMargin(vec3 x, vec3 xi) {
    vec3 moved = x - xi;
    return dot(moved, moved) < PBF_STEP_MARGIN * PBF_STEP_MARGIN;
}

#endif // !__cplusplus

#endif // SLUICE_SHARED_COLLIDERS_NEAR_GLSL_H
