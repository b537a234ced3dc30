// GLSL only: the fixed-point sums of shared/Bodies.h (`bodySums`, which the including pass
// declares after glsl/PbfGlsl.h): reading a body's reaction in the body pass or a measured
// collider's force in pbf_collider_forces.comp, and the measured colliders' moment scale.
#ifndef SLUICE_SHARED_BODY_SUMS_GLSL_H
#define SLUICE_SHARED_BODY_SUMS_GLSL_H

#ifndef __cplusplus

// Component `axis` of body b's fixed-point sum that starts at word `sum` (shared/Bodies.h):
// its positive part less its negative part, as a double (exact below 2^53).
double sumAt(uint b, uint sum, uint axis) {
    uint lo = bodySumWord(b, sum, axis);
    double positive = double(bodySums[lo + 1u]) * 4294967296.0 + double(bodySums[lo]);
    uint neg = lo + kBodySumNegative;
    double negative = double(bodySums[neg + 1u]) * 4294967296.0 + double(bodySums[neg]);
    return positive - negative;
}

// Body b's vector sum that starts at word `sum`.
vec3 sumOf(uint b, uint sum) {
    return vec3(sumAt(b, sum, 0u), sumAt(b, sum, 1u), sumAt(b, sum, 2u));
}

// Fixed-point units per m^2 of collider c's measured moment sums (a push times its arm from
// forcePoint): kSumUnitsPerH / h over the farthest its grid box (and h beyond it) reaches from its
// origin, so no arm overflows one add. pbf_delta.comp sums with it, pbf_collider_forces.comp
// reads with it.
float solidMomentScale(uint c) {
    vec3 corner = max(abs(colliders[c].origin), abs(colliders[c].boxMax));
    return kSumUnitsPerH * P.invH / (colliders[c].scale * length(corner) + PBF_H);
}

#endif // !__cplusplus

#endif // SLUICE_SHARED_BODY_SUMS_GLSL_H
