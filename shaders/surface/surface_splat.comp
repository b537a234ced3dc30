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
    // Block by block, so the block map is read once per block, not once per sample; rows
    // along x are clipped to the support sphere before the loop.
    int side = int(kSurfaceBlockSide);
    ivec3 blo = lo / side;
    ivec3 bhi = hi / side;
    for (int bz = blo.z; bz <= bhi.z; ++bz)
        for (int by = blo.y; by <= bhi.y; ++by)
            for (int bx = blo.x; bx <= bhi.x; ++bx) {
                ivec3 b = ivec3(bx, by, bz);
                uint index = blockIndex(b);
                if (blockFlag[index] == 0u)
                    continue;
                uint base = blockSlot[index] * kSurfaceBlockSamples;
                ivec3 from = max(lo, b * side);
                ivec3 to = min(hi, b * side + side - 1);
                for (int z = from.z; z <= to.z; ++z) {
                    float dz = uOrigin.z + float(z) * uCell - p.z;
                    for (int y = from.y; y <= to.y; ++y) {
                        float dy = uOrigin.y + float(y) * uCell - p.y;
                        float ryz = dy * dy + dz * dz;
                        if (ryz >= h2)
                            continue;
                        for (int x = from.x; x <= to.x; ++x) {
                            float dx = uOrigin.x + float(x) * uCell - p.x;
                            float q = h2 - ryz - dx * dx;
                            if (q <= 0.0)
                                continue;
                            uint add = uint(scale * q * q * q + 0.5);
                            ivec3 local = ivec3(x, y, z) - b * side;
                            if (add != 0u)
                                atomicAdd(field[base + laneOf(local)], add);
                        }
                    }
                }
            }
}
