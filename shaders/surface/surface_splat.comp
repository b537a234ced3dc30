// The field: every particle adds V W(|x - x_j|) to the samples within its kernel (poly6,
// support uSupport), in fixed point with integer atomics, so any order gives the same sums.
#version 450 core

#include "shared/SurfaceGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

layout(std430, binding = kSurfBindPoints) readonly buffer Points { vec4 points[]; };

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uCount)
        return;
    vec3 p = points[i].xyz;
    vec3 g = (p - uOrigin) / uCell;
    float reach = uSupport / uCell;
    ivec3 lo = max(ivec3(ceil(g - reach)), ivec3(0));
    ivec3 hi = min(ivec3(floor(g + reach)), uSamples - 1);
    float h2 = uSupport * uSupport;
    // poly6: 315 / (64 pi h^9) (h^2 - r^2)^3, times the particle volume and the fixed scale.
    float scale = uVolume * kSurfaceFixedScale * 315.0 /
                  (64.0 * 3.14159265358979 * h2 * h2 * h2 * h2 * uSupport);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
                ivec3 s = ivec3(x, y, z);
                vec3 d = uOrigin + vec3(s) * uCell - p;
                float r2 = dot(d, d);
                if (r2 >= h2)
                    continue;
                float q = h2 - r2;
                uint add = uint(scale * q * q * q + 0.5);
                uint slot = sampleSlot(s);
                if (add != 0u && slot != 0xffffffffu)
                    atomicAdd(field[slot], add);
            }
}
