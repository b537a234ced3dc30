// Screen-space fluid surface (van der Laan, Green and Sainz 2009), smoothing: one pass of a
// bilateral filter over the fluid's view depth, in both directions at once (a separable
// version leaves streaks along its last direction where the range weight cuts it). The spatial
// radius is a fixed world size projected at the pixel's depth, at most kFluidSmoothReach pixels
// (a strided, sparser kernel shows its grid); repeated passes widen it. The range weight keeps
// separate sheets of fluid apart. Empty pixels (depth 0) stay empty and never contribute, so
// the outline does not grow.
// A work group filters a tile of kFluidSmoothTile^2 pixels from a copy in shared memory of the
// tile and kFluidSmoothReach pixels around it: each depth is read from the texture about four
// times rather than up to (2 kFluidSmoothReach + 1)^2 times (on an H200 at 1920x1080 the
// fragment-shader version, a texture fetch per tap, took 1.7 ms a pass).
#version 450 core

#include "glsl/RenderGlsl.h"

layout(local_size_x = kFluidSmoothTile, local_size_y = kFluidSmoothTile) in;

layout(binding = kRenderUnitFluidDepth) uniform sampler2D uDepth;
layout(binding = kRenderImageFluidSmooth, r32f) writeonly uniform image2D outDepth;
uniform float uWorldRadius;  // filter radius [m]
uniform float uDepthFalloff; // depth difference that weighs e^-1 [m]

const int kReach = int(kFluidSmoothReach);
const int kSide = int(kFluidSmoothTile) + 2 * kReach; // the shared copy's side
shared float tile[kSide * kSide];

void main() {
    ivec2 size = textureSize(uDepth, 0);
    ivec2 corner = ivec2(gl_WorkGroupID.xy) * int(kFluidSmoothTile) - kReach;
    // The copy, clamped at the image's edges as texelFetch of a clamped position reads it.
    for (uint k = gl_LocalInvocationIndex; k < uint(kSide * kSide);
         k += kFluidSmoothTile * kFluidSmoothTile) {
        ivec2 q = clamp(corner + ivec2(int(k) % kSide, int(k) / kSide), ivec2(0), size - 1);
        tile[k] = texelFetch(uDepth, q, 0).r;
    }
    barrier();

    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size)))
        return;
    ivec2 t = ivec2(gl_LocalInvocationID.xy) + kReach; // p in the copy
    float z = tile[t.y * kSide + t.x];
    if (z <= 0.0) {
        imageStore(outDepth, p, vec4(0.0));
        return;
    }
    // Pixels per metre at depth z: proj[1][1] is cot(fov / 2); the viewport is 2 NDC units tall.
    float pixels = clamp(uWorldRadius * F.proj[1][1] * 0.5 * F.viewportSize.y / z, 1.0,
                         float(kReach));
    int taps = int(ceil(pixels));
    float sigma = 0.5 * pixels;
    float sum = 0.0;
    float weights = 0.0;
    for (int j = -taps; j <= taps; ++j) {
        for (int i = -taps; i <= taps; ++i) {
            vec2 offset = vec2(i, j);
            float zi = tile[(t.y + j) * kSide + t.x + i];
            if (zi <= 0.0)
                continue;
            float dz = (zi - z) / uDepthFalloff;
            float w = exp(-dot(offset, offset) / (2.0 * sigma * sigma) - dz * dz);
            sum += w * zi;
            weights += w;
        }
    }
    imageStore(outDepth, p, vec4(sum / weights));
}
