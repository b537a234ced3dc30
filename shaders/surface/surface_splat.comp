// The field: every particle adds V W to the samples within its kernel (poly6 of support
// uSupport, of |x - x_j| or, anisotropic, of |G (x - c_j)|), in fixed point with integer
// atomics, so any order gives the same sums.
#version 450 core

#include "glsl/SurfaceKernelGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uCount)
        return;
    SurfaceKernel k = kernelOf(i);
    vec3 p = k.centre;
    vec3 g = (p - uOrigin) / uCell;
    vec3 reach = k.extent / uCell;
    ivec3 lo = max(ivec3(ceil(g - reach)), ivec3(0));
    ivec3 hi = min(ivec3(floor(g + reach)), uSamples - 1);
    float h2 = uSupport * uSupport;
    // poly6: 315 / (64 pi h^9) (h^2 - r^2)^3, times the particle volume and the fixed scale
    // (det G = 1: an anisotropic kernel holds the sphere's volume).
    float scale = particleWeight(i) * uVolume * kSurfaceFixedScale * 315.0 /
                  (64.0 * 3.14159265358979 * h2 * h2 * h2 * h2 * uSupport);
    // Block by block, so the block map is read once per block, not once per sample; a
    // sphere's rows along x are clipped to it before the loop, an ellipsoid's x range solved
    // per row (|G d|^2 = d^T G^2 d is a quadratic in d.x: a x^2 + 2 b x + c).
    mat3 g2 = k.g * k.g;
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
                        if (!uAnisotropic && ryz >= h2)
                            continue;
                        int first = from.x;
                        int last = to.x;
                        if (uAnisotropic) {
                            float b = g2[1][0] * dy + g2[2][0] * dz;
                            float c = dot(vec2(dy, dz), mat2(g2[1].yz, g2[2].yz) * vec2(dy, dz));
                            float disc = b * b - g2[0][0] * (c - h2);
                            if (disc <= 0.0)
                                continue;
                            // One sample wider each way: q decides at the ends, as for a sphere.
                            float root = sqrt(disc);
                            float x0 = p.x + (-b - root) / g2[0][0];
                            float x1 = p.x + (-b + root) / g2[0][0];
                            first = max(first, int(floor((x0 - uOrigin.x) / uCell)));
                            last = min(last, int(ceil((x1 - uOrigin.x) / uCell)));
                        }
                        for (int x = first; x <= last; ++x) {
                            float dx = uOrigin.x + float(x) * uCell - p.x;
                            float q;
                            if (uAnisotropic) {
                                vec3 u = k.g * vec3(dx, dy, dz);
                                q = h2 - dot(u, u);
                            } else {
                                q = h2 - ryz - dx * dx;
                            }
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
