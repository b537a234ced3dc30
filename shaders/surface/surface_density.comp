// The density-normalised field (SurfaceOptions::densityNormalised): each particle's own density
// as a share of the rest density is the field at its centre (trilinear between the samples),
// and its weight in the field's second pass is the inverse, so a particle with few neighbours
// (a thin sheet, a droplet) counts for the volume it has, as in splashsurf's colour field.
#version 450 core

#include "glsl/SurfaceGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

layout(std430, binding = kSurfBindPoints) readonly buffer Points { vec4 points[]; };
layout(std430, binding = kSurfBindWeights) writeonly buffer Weights { float weights[]; };

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uCount)
        return;
    vec3 g = (points[i].xyz - uOrigin) / uCell;
    ivec3 s = ivec3(floor(g));
    vec3 f = g - vec3(s);
    float density = 0.0;
    for (uint c = 0u; c < 8u; ++c) {
        uint slot = sampleSlot(s + cornerOffset(c)); // stored: within a cell of a particle
        if (slot != 0xffffffffu)
            density += cornerWeight(f, c) * float(field[slot]) * (1.0 / kSurfaceFixedScale);
    }
    weights[i] = 1.0 / max(density, kSurfaceDensityFloor);
}
