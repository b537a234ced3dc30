// Sphere impostors, vertex half: one camera-facing square per particle, expanded from the
// position buffer (6 vertices per particle, no vertex buffer), just large enough to hold the
// sphere's exact perspective outline, in the plane of the sphere's front point so the hit the
// fragment half finds is never nearer than the square (conservative depth: early depth tests
// stay on). With SLUICE_PARTICLE_LIST the particles are the ones render_splat.comp listed as
// too large for it; otherwise all of them in the solver's sorted (cell) order, reversed when
// F.reverseOrder is 1: whichever of the two runs nearer to front to back for the camera.
#version 450 core

#include "glsl/RenderGlsl.h"

layout(std430, binding = kRenderBindPositions) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = kRenderBindVelocities) readonly buffer Velocities { vec4 velocities[]; };
#ifdef SLUICE_PARTICLE_LIST
layout(std430, binding = kRenderBindSplatList) readonly buffer List { uint listed[]; };
#endif

out vec3 vViewPos;       // this corner of the square, view space [m]
flat out vec3 vCentre;   // sphere centre, view space [m]
flat out vec4 vVelocity; // world velocity [m/s], density error C_i in w

const vec2 kCorners[6] = vec2[6](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0),
                                 vec2(-1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0));

void main() {
    uint k = uint(gl_VertexID) / 6u;
#ifdef SLUICE_PARTICLE_LIST
    uint i = listed[k];
#else
    uint i = F.reverseOrder != 0u ? F.particleCount - 1u - k : k;
#endif
    vec2 corner = kCorners[uint(gl_VertexID) % 6u];
    vec3 centre = (F.view * vec4(positions[i].xyz, 1.0)).xyz;
#if defined(SLUICE_FLUID_DEPTH) || defined(SLUICE_THICKNESS)
    float r = F.fluidSphereRadius; // larger than the particles, so the lattice leaves no holes
#else
    float r = F.particleRadius;
#endif
    vCentre = centre;
    vVelocity = velocities[i];
    vec3 origin, u, v;
    // w = 1: a removed particle the solver has not compacted away yet (Simulation.h).
    if (positions[i].w != 0.0 || !sphereSquare(centre, r, origin, u, v)) {
        // The eye is inside this sphere (or the position is not finite): draw nothing.
        vViewPos = centre;
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    vViewPos = origin + corner.x * u + corner.y * v;
    gl_Position = F.proj * vec4(vViewPos, 1.0);
}
