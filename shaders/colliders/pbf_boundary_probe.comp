// The walls' and static colliders' boundary volume at world points, as the lambda pass adds it
// to a particle's density (BoundaryVolumeGlsl.h): Simulation::solidBoundaryAt runs it for
// tests and tools. Not part of a step.
#version 450 core

#define PBF_WITH_COLLIDERS 1
#include "glsl/PbfGlsl.h"
#include "glsl/BoundaryVolumeGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindPosIn) readonly buffer Points { vec4 points[]; }; // xyz [m]
// xyz: the share's gradient [1/m]; w: the share (of the density over rho0).
layout(std430, binding = kBindPosOut) writeonly buffer Shares { vec4 shares[]; };

uniform uint uCount;

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uCount)
        return;
    float share = 0.0;
    vec3 gradient = vec3(0.0);
    addColliderBoundary(points[i].xyz, share, gradient);
    addWallBoundary(points[i].xyz, share, gradient);
    shares[i] = vec4(gradient, share);
}
