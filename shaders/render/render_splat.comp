// Sphere impostors drawn by compute passes, for the spheres that cover a few pixels: a GPU's
// rasteriser spends most of its time on such tiny squares (two triangles, 2x2 pixel quads, a
// depth write), and some (NVIDIA's H100 and H200) have little of it. One invocation per
// particle walks the pixels of its square's screen box and solves the same ray-sphere hit per
// pixel centre as render_particles.frag. Each pixel keeps the nearest hit, in two passes over
// the particles, then render_splat_resolve.frag shades it:
//   default              the nearest window depth per pixel, by atomicMin on its bits (depths
//                        in [0, 1] order as their bits do), in front of the opaque scene only;
//                        particles whose box is wider or taller than kSplatMaxSide pixels are
//                        listed for the impostor draw instead (6 vertices each, indirect)
//   SLUICE_SPLAT_WINNER  the lowest index among the particles whose hit has that depth: equal
//                        depths (touching spheres, at 32-bit depth precision) resolve the same
//                        way every run, whatever order the invocations ran in
//   SLUICE_SPLAT_THICKNESS  the screen-space fluid's thickness: every hit's chord, weighted as
//                        render_particles.frag weighs it, summed in fixed point (order-free)
// The spheres have radius uRadius: the particles' own, or the fluid surface's larger ones.
// Rays through the pixel centres, so a pixel is covered exactly when the impostor draw covers
// it (render_particles.vert's square contains the sphere's outline, and this box the square).
#version 450 core

#include "shared/ChunkedDispatch.h"
#include "glsl/RenderGlsl.h"

layout(local_size_x = kSplatLocalSize) in;

layout(std430, binding = kRenderBindPositions) readonly buffer Positions { vec4 positions[]; };
layout(binding = kRenderUnitSceneDepth) uniform sampler2D sceneDepth;
uniform float uRadius; // [m]

#if defined(SLUICE_SPLAT_WINNER)
layout(binding = kRenderImageSplatDepth, r32ui) readonly uniform uimage2D nearest;
layout(binding = kRenderImageSplatWinner, r32ui) uniform uimage2D winner;
#elif defined(SLUICE_SPLAT_THICKNESS)
layout(binding = kRenderImageSplatThickness, r32ui) uniform uimage2D thickness;
#else
layout(binding = kRenderImageSplatDepth, r32ui) coherent uniform uimage2D nearest;
layout(std430, binding = kRenderBindSplatList) writeonly buffer List { uint listed[]; };
layout(std430, binding = kRenderBindSplatArgs) buffer Args { SplatDrawArgs args; };
#endif

// Window position [pixels] of a view-space point in front of the eye.
vec2 windowOf(vec3 p) {
    vec4 clip = F.proj * vec4(p, 1.0);
    return (0.5 * clip.xy / clip.w + 0.5) * F.viewportSize;
}

// The pixels whose centres the square of the sphere (centre, r) may cover, clipped to the image:
// lo .. hi inclusive (empty when lo > hi). False when the impostor draw must handle it: the
// square reaches behind the near plane (the rasteriser clips it).
bool screenBox(vec3 origin, vec3 u, vec3 v, out ivec2 lo, out ivec2 hi) {
    vec2 minWin = vec2(1e30), maxWin = vec2(-1e30);
    for (int k = 0; k < 4; ++k) {
        vec3 p = origin + ((k & 1) != 0 ? u : -u) + ((k & 2) != 0 ? v : -v);
        if (-p.z <= F.nearPlane)
            return false;
        vec2 w = windowOf(p);
        minWin = min(minWin, w);
        maxWin = max(maxWin, w);
    }
    // Pixel x covers centre x + 0.5.
    lo = max(ivec2(ceil(minWin - 0.5)), ivec2(0));
    hi = min(ivec2(floor(maxWin - 0.5)), ivec2(F.viewportSize) - 1);
    return true;
}

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    // w = 1: a removed particle the solver has not compacted away yet (Simulation.h).
    if (i >= F.particleCount || positions[i].w != 0.0)
        return;
    float r = uRadius;
    vec3 centre = (F.view * vec4(positions[i].xyz, 1.0)).xyz;
    vec3 origin, u, v;
    if (!sphereSquare(centre, r, origin, u, v))
        return; // the eye is inside it, or it is not finite: drawn by neither pass
    ivec2 lo, hi;
    bool boxed = screenBox(origin, u, v, lo, hi);
    if (!boxed || any(greaterThan(hi - lo, ivec2(int(kSplatMaxSide) - 1)))) {
#if !defined(SLUICE_SPLAT_WINNER) && !defined(SLUICE_SPLAT_THICKNESS)
        listed[atomicAdd(args.vertexCount, 6u) / 6u] = i;
#endif
        return;
    }
    for (int y = lo.y; y <= hi.y; ++y) {
        for (int x = lo.x; x <= hi.x; ++x) {
            ivec2 p = ivec2(x, y);
            vec3 rd = viewRayOfPixel(vec2(p) + 0.5);
            vec3 hit;
            float chord;
            if (!sphereHit(rd, centre, r, hit, chord))
                continue;
            float depth = windowDepthOfView(hit);
            if (depth >= texelFetch(sceneDepth, p, 0).r)
                continue;
#if defined(SLUICE_SPLAT_WINNER)
            if (imageLoad(nearest, p).r == floatBitsToUint(depth))
                imageAtomicMin(winner, p, i);
#elif defined(SLUICE_SPLAT_THICKNESS)
            // Metres of water: each particle stands for a cube of the rest spacing (2 r0)^3,
            // its sphere holds 4/3 pi r^3.
            float r0 = F.particleRadius;
            float metres = chord * (8.0 * r0 * r0 * r0) / (4.18879 * r * r * r);
            imageAtomicAdd(thickness, p, uint(metres * kSplatThicknessScale + 0.5));
#else
            imageAtomicMin(nearest, p, floatBitsToUint(depth));
#endif
        }
    }
}
