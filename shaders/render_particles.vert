// Sphere impostors, vertex half: one camera-facing square per particle, expanded from the
// position buffer (6 vertices per particle, no vertex buffer), just large enough to hold the
// sphere's exact perspective outline. The fragment half solves the ray-sphere hit per pixel.
#version 450 core

#include "shared/RenderGlsl.h"

layout(std430, binding = kRenderBindPositions) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = kRenderBindVelocities) readonly buffer Velocities { vec4 velocities[]; };

out vec3 vViewPos;       // this corner of the square, view space [m]
flat out vec3 vCentre;   // sphere centre, view space [m]
flat out vec4 vVelocity; // world velocity [m/s], density error C_i in w

const vec2 kCorners[6] = vec2[6](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0),
                                 vec2(-1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0));

void main() {
    uint i = uint(gl_VertexID) / 6u;
    vec2 corner = kCorners[uint(gl_VertexID) % 6u];
    vec3 centre = (F.view * vec4(positions[i].xyz, 1.0)).xyz;
#if defined(SLUICE_FLUID_DEPTH) || defined(SLUICE_THICKNESS)
    float r = F.fluidSphereRadius; // larger than the particles, so the lattice leaves no holes
#else
    float r = F.particleRadius;
#endif
    float d = length(centre);
    vCentre = centre;
    vVelocity = velocities[i];
    vViewPos = centre;
    if (!(d > 1.001 * r)) {
        // The eye is inside this sphere (or the position is not finite): draw nothing.
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    vec3 w = centre / d;
    vec3 helper = abs(w.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 u = normalize(cross(helper, w));
    vec3 v = cross(w, u);
    // The cone of rays from the eye tangent to the sphere cuts the plane through the centre,
    // normal to the eye direction, in a circle of radius r d / sqrt(d^2 - r^2).
    float halfSize = r * d / sqrt(d * d - r * r);
    vViewPos = centre + halfSize * (corner.x * u + corner.y * v);
    gl_Position = F.proj * vec4(vViewPos, 1.0);
}
