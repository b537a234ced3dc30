// Samples colliders at points: phi and its gradient in each collider's local frame, as the
// solver reads them (sampleCollider, dense or sparse). The sampler parity tests and the
// collision benchmark run it; the solver does not.
#version 450 core

#define PBF_WITH_COLLIDERS 1
#include "glsl/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

// xyz: the point in the collider's local frame [asset units]; w: the collider's index (bits).
layout(std430, binding = kBindPosIn) readonly buffer Points { vec4 points[]; };
// xyz: grad phi; w: phi [asset units].
layout(std430, binding = kBindPosOut) writeonly buffer Samples { vec4 samples[]; };

uniform uint uCount;

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uCount)
        return;
    float phi;
    vec3 grad;
    sampleCollider(floatBitsToUint(points[i].w), points[i].xyz, phi, grad);
    samples[i] = vec4(grad, phi);
}
