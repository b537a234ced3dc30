// The sealed contacts' bands and the film model's level over a body (docs/bodies.md, "Sealed
// contacts" and "The film under a body"): the delta and body passes. Include after
// glsl/PbfGlsl.h.
#ifndef SLUICE_FILM_GLSL_H
#define SLUICE_FILM_GLSL_H

// How far from a wall or a static collider [m] a body's face over it counts as sealed
// (docs/bodies.md, "The film under a body"): within h + kSealedBandRadii particle radii (1.25
// spacings), where the water under the face is at most three layers thick and the film model
// holds it at the pressure of the water over it. The rim is the water beside a body within
// one particle radius more of the solid.
float sealedBand() {
    return PBF_H + kSealedBandRadii * PBF_RADIUS;
}
float rimBand() {
    return sealedBand() + PBF_RADIUS;
}

// Up: against gravity (+y without it).
vec3 upOf() {
    float g = length(P.gravity);
    return g > 0.0 ? -P.gravity / g : vec3(0.0, 1.0, 0.0);
}

#ifdef PBF_WITH_BODIES
// The film model's water level over body b (docs/bodies.md, "The film under a body"): the
// delta pass maxes into the body's `surface` word the height of each compressed particle
// (lambda != 0) in the column over the body (horizontal distance under its bound radius + h),
// above the body's centre less surfaceBase, in units of h / kSurfaceUnits.
const float kSurfaceUnits = 65536.0;
float surfaceBase(uint b) {
    return 2.0 * bodies[b].boundRadius + 4.0 * PBF_H;
}
uint surfaceWordOf(uint b, vec3 x) {
    vec3 up = upOf();
    vec3 d = x - bodies[b].position;
    float height = dot(d, up);
    vec3 across = d - height * up;
    float reach = bodies[b].boundRadius + PBF_H;
    if (dot(across, across) >= reach * reach)
        return 0u;
    return uint(clamp(height + surfaceBase(b), 0.0, 4000.0 * PBF_H) / PBF_H * kSurfaceUnits);
}
// The level [m along up] from the word: the highest compressed particle lies about a spacing
// under the free surface's top layer, whose centres lie a radius under the level; measured in
// the tests' tank, the level by volume is the particle's height plus 2 r (docs/bodies.md).
float surfaceLevel(uint b, uint word) {
    return dot(bodies[b].position, upOf()) - surfaceBase(b) +
           float(word) / kSurfaceUnits * PBF_H + 2.0 * PBF_RADIUS;
}
#endif

#endif // SLUICE_FILM_GLSL_H
