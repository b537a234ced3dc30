// Screen-space fluid surface (van der Laan, Green and Sainz 2009), smoothing: one pass of a
// bilateral filter over the fluid's view depth, in both directions at once (a separable
// version leaves streaks along its last direction where the range weight cuts it). The spatial
// radius is a fixed world size projected at the pixel's depth, at most kMaxTaps pixels (a
// strided, sparser kernel shows its grid); repeated passes widen it. The range weight keeps
// separate sheets of fluid apart. Empty pixels (depth 0) stay empty and never contribute, so
// the outline does not grow.
#version 450 core

#include "shared/RenderGlsl.h"

layout(binding = kRenderUnitFluidDepth) uniform sampler2D uDepth;
uniform float uWorldRadius;  // filter radius [m]
uniform float uDepthFalloff; // depth difference that weighs e^-1 [m]

in vec2 vUv;
layout(location = 0) out float outDepth;

const int kMaxTaps = 8; // pixels per side and axis

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(uDepth, 0) - 1;
    float z = texelFetch(uDepth, p, 0).r;
    if (z <= 0.0) {
        outDepth = 0.0;
        return;
    }
    // Pixels per metre at depth z: proj[1][1] is cot(fov / 2); the viewport is 2 NDC units tall.
    float pixels = clamp(uWorldRadius * F.proj[1][1] * 0.5 * F.viewportSize.y / z, 1.0,
                         float(kMaxTaps));
    int taps = int(ceil(pixels));
    float sigma = 0.5 * pixels;
    float sum = 0.0;
    float weights = 0.0;
    for (int j = -taps; j <= taps; ++j) {
        for (int i = -taps; i <= taps; ++i) {
            vec2 offset = vec2(i, j);
            float zi = texelFetch(uDepth, clamp(p + ivec2(i, j), ivec2(0), last), 0).r;
            if (zi <= 0.0)
                continue;
            float dz = (zi - z) / uDepthFalloff;
            float w = exp(-dot(offset, offset) / (2.0 * sigma * sigma) - dz * dz);
            sum += w * zi;
            weights += w;
        }
    }
    outDepth = sum / weights;
}
