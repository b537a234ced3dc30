// Sphere impostors, fragment half: the exact ray-sphere hit of this pixel's view ray, with its
// window depth, so spheres intersect each other and the colliders correctly. Three variants:
//   default              shaded colour (water, speed or density error)
//   SLUICE_FLUID_DEPTH   the hit's view depth [m], for the screen-space fluid surface
//   SLUICE_THICKNESS     the ray's chord through the sphere [m], summed by additive blending
// The fluid variants test against the opaque scene's depth themselves (sampled, not attached).
#version 450 core

#include "shared/RenderGlsl.h"

in vec3 vViewPos;
flat in vec3 vCentre;
flat in vec4 vVelocity;

#if defined(SLUICE_FLUID_DEPTH) || defined(SLUICE_THICKNESS)
layout(binding = kRenderUnitSceneDepth) uniform sampler2D sceneDepth;
layout(location = 0) out float outValue;
#else
layout(location = 0) out vec4 outColour;
#endif

void main() {
    vec3 rd = normalize(vViewPos);
#if defined(SLUICE_FLUID_DEPTH) || defined(SLUICE_THICKNESS)
    float r = F.fluidSphereRadius; // larger than the particles, so the lattice leaves no holes
#else
    float r = F.particleRadius;
#endif
    float b = dot(rd, vCentre);
    float c = dot(vCentre, vCentre) - r * r;
    float disc = b * b - c;
    if (disc < 0.0)
        discard;
    float s = sqrt(disc);
    vec3 hit = (b - s) * rd;
    float depth = windowDepthOfView(hit);
    gl_FragDepth = depth;
#if defined(SLUICE_FLUID_DEPTH) || defined(SLUICE_THICKNESS)
    if (depth >= texelFetch(sceneDepth, ivec2(gl_FragCoord.xy), 0).r)
        discard;
#if defined(SLUICE_FLUID_DEPTH)
    outValue = -hit.z;
#else
    // The chord, weighted so the sum is metres of water: each particle stands for a cube of
    // the rest spacing (2 r0)^3, its sphere holds 4/3 pi r^3.
    float r0 = F.particleRadius;
    outValue = 2.0 * s * (8.0 * r0 * r0 * r0) / (4.18879 * r * r * r);
#endif
#else
    vec3 n = mat3(F.invView) * ((hit - vCentre) / r);
    vec3 toEye = -(mat3(F.invView) * rd);
    uint mode = F.colourMode;
    vec3 colour;
    if (mode == kColourSpeed) {
        colour = shade(colourMap(length(vVelocity.xyz) / F.speedRange), n, toEye, 0.25, 40.0);
    } else if (mode == kColourDensityError) {
        colour = shade(colourMap(vVelocity.w / F.densityErrorRange), n, toEye, 0.25, 40.0);
    } else {
        colour = shade(F.waterColour, n, toEye, 0.6, 60.0);
        // A little sky reflected at grazing angles (Schlick's Fresnel term, F0 = 0.02).
        float fresnel = 0.02 + 0.98 * pow(1.0 - max(dot(n, toEye), 0.0), 5.0);
        colour = mix(colour, skyColour(reflect(-toEye, n)), 0.6 * fresnel);
    }
    outColour = vec4(colour, 1.0);
#endif
}
