// Sphere impostors, fragment half: the exact ray-sphere hit of this pixel's view ray, with its
// window depth, so spheres intersect each other and the colliders correctly. The square lies in
// front of the sphere, so the depth written is never less than the square's: declared with
// depth_greater, the GPU keeps testing depth before the shader runs. Three variants:
//   default              shaded colour (water, speed or density error)
//   SLUICE_FLUID_DEPTH   the hit's view depth [m], for the screen-space fluid surface
//   SLUICE_THICKNESS     the ray's chord through the sphere [m], summed by additive blending
// The fluid variants test against the opaque scene's depth themselves (sampled, not attached).
#version 450 core

#include "glsl/RenderGlsl.h"

in vec3 vViewPos;
flat in vec3 vCentre;
flat in vec4 vVelocity;

#if defined(SLUICE_FLUID_DEPTH) || defined(SLUICE_THICKNESS)
layout(binding = kRenderUnitSceneDepth) uniform sampler2D sceneDepth;
layout(location = 0) out float outValue;
#else
layout(location = 0) out vec4 outColour;
#endif
#ifndef SLUICE_THICKNESS
layout(depth_greater) out float gl_FragDepth;
#endif

void main() {
    // The ray through the pixel centre, computed as render_splat.comp computes it (not from
    // vViewPos), so both draw the same pixels with the same colours.
    vec3 rd = viewRayOfPixel(gl_FragCoord.xy);
#if defined(SLUICE_FLUID_DEPTH) || defined(SLUICE_THICKNESS)
    float r = F.fluidSphereRadius; // larger than the particles, so the lattice leaves no holes
#else
    float r = F.particleRadius;
#endif
    vec3 hit;
    float chord;
    if (!sphereHit(rd, vCentre, r, hit, chord))
        discard;
    // Never nearer than the square (rounding could put a grazing hit a hair in front of it).
    float depth = max(windowDepthOfView(hit), gl_FragCoord.z);
#if defined(SLUICE_FLUID_DEPTH) || defined(SLUICE_THICKNESS)
    if (depth >= texelFetch(sceneDepth, ivec2(gl_FragCoord.xy), 0).r)
        discard;
#if defined(SLUICE_FLUID_DEPTH)
    gl_FragDepth = depth;
    outValue = -hit.z;
#else
    // The chord, weighted so the sum is metres of water: each particle stands for a cube of
    // the rest spacing (2 r0)^3, its sphere holds 4/3 pi r^3.
    float r0 = F.particleRadius;
    outValue = chord * (8.0 * r0 * r0 * r0) / (4.18879 * r * r * r);
#endif
#else
    gl_FragDepth = depth;
    outColour = vec4(sphereColour(rd, hit, vCentre, r, vVelocity), 1.0);
#endif
}
