// The Gaussian field's first step: every particle adds its trilinear weights to the eight
// samples round it, in fixed point with integer atomics (any order gives the same sums). The
// three blur passes (surface_blur.comp) then spread the deposit with the Gaussian.
#version 450 core

#include "glsl/SurfaceKernelGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uCount)
        return;
    vec3 g = (points[i].xyz - uOrigin) / uCell;
    ivec3 s = ivec3(floor(g));
    vec3 f = g - vec3(s);
    float weight = particleWeight(i) * kSurfaceDepositScale;
    for (uint c = 0u; c < 8u; ++c) {
        uint add = uint(cornerWeight(f, c) * weight + 0.5);
        uint slot = sampleSlot(s + cornerOffset(c));
        // Every sample within a cell of a particle is stored (surface_mark.comp).
        if (add != 0u && slot != 0xffffffffu)
            atomicAdd(field[slot], add);
    }
}
