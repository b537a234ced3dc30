// The field, gathered: one work group per stored block and one invocation per row of its
// samples along x. The particles whose kernels reach the block are read from the block runs of
// the blocks around it (surface_bin_*.comp), a round of candidates at a time into shared
// memory, and every row sums what each adds to its 8 samples, V W rounded to fixed point per
// particle and sample as the scattering splat did, so the integer sums are the same in any
// order, with no atomics on the field.
#version 450 core

#include "shared/SurfaceKernelGlsl.h"

layout(local_size_x = kSurfaceBlockRows) in;

layout(std430, binding = kSurfBindBinStart) readonly buffer BinStart { uint binStart[]; };
layout(std430, binding = kSurfBindBinParticles) readonly buffer BinParticles {
    uint binParticles[];
};

uniform uint uBinCount;  // blocks in the grid (binStart's length)
uniform uint uParticles; // particles binned
uniform int uBinReach;   // blocks beyond its own a kernel may reach, along each axis

// Candidates read per round: kSurfaceGatherPerRow per invocation.
const uint kRound = kSurfaceGatherPerRow * kSurfaceBlockRows;
shared vec4 sKernel[3u * kRound];
shared uint sListed;

uint binEnd(uint b) {
    return b + 1u < uBinCount ? binStart[b + 1u] : uParticles;
}

// The candidates: the runs of the blocks lo .. hi, one run per (y, z) row of blocks (the blocks
// along x are next to each other in the block order, and so are their runs).
uint runStart(int by, int bz, ivec3 lo) {
    return binStart[blockIndex(ivec3(lo.x, by, bz))];
}

uint runEnd(int by, int bz, ivec3 hi) {
    return binEnd(blockIndex(ivec3(hi.x, by, bz)));
}

uint candidate(uint c, ivec3 lo, ivec3 hi) {
    for (int bz = lo.z; bz <= hi.z; ++bz)
        for (int by = lo.y; by <= hi.y; ++by) {
            uint start = runStart(by, bz, lo);
            uint n = runEnd(by, bz, hi) - start;
            if (c < n)
                return binParticles[start + c];
            c -= n;
        }
    return 0u; // c < the total: not reached
}

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockRows;
    uint row = gl_LocalInvocationID.x;
    if (slot >= uCount) // uniform over the group
        return;
    ivec3 b = blockCoord(activeBlock[slot]);
    ivec3 first = b * int(kSurfaceBlockSide);
    ivec3 last = first + int(kSurfaceBlockSide) - 1;
    int y = first.y + int(row & 7u);
    int z = first.z + int(row >> 3u);
    float h2 = uSupport * uSupport;
    // poly6: 315 / (64 pi h^9) (h^2 - r^2)^3, times the particle volume and the fixed scale
    // (det G = 1: an anisotropic kernel holds the sphere's volume).
    float scale = uVolume * kSurfaceFixedScale * 315.0 /
                  (64.0 * 3.14159265358979 * h2 * h2 * h2 * h2 * uSupport);
    ivec3 lo = max(b - uBinReach, ivec3(0));
    ivec3 hi = min(b + uBinReach, uBlocks - 1);
    uint total = 0u;
    for (int bz = lo.z; bz <= hi.z; ++bz)
        for (int by = lo.y; by <= hi.y; ++by)
            total += runEnd(by, bz, hi) - runStart(by, bz, lo);
    uint acc[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    for (uint start = 0u; start < total; start += kRound) { // uniform over the group
        if (row == 0u)
            sListed = 0u;
        barrier();
        // The round's candidates whose kernel's box meets the block's samples, in any order.
        for (uint i = 0u; i < kSurfaceGatherPerRow; ++i) {
            uint c = start + row + i * kSurfaceBlockRows;
            if (c >= total)
                break;
            SurfaceKernel k = kernelOf(candidate(c, lo, hi));
            vec3 g = (k.centre - uOrigin) / uCell;
            vec3 reach = k.extent / uCell;
            if (any(greaterThan(ivec3(ceil(g - reach)), last)) ||
                any(lessThan(ivec3(floor(g + reach)), first)))
                continue;
            uint at = atomicAdd(sListed, 1u);
            sKernel[3u * at] = vec4(k.centre, 0.0);
            sKernel[3u * at + 1u] = vec4(k.g[0][0], k.g[0][1], k.g[0][2], k.g[1][1]);
            sKernel[3u * at + 2u] = vec4(k.g[1][2], k.g[2][2], 0.0, 0.0);
        }
        barrier();
        uint listed = sListed;
        for (uint m = 0u; m < listed; ++m) {
            vec3 p = sKernel[3u * m].xyz;
            float dz = uOrigin.z + float(z) * uCell - p.z;
            float dy = uOrigin.y + float(y) * uCell - p.y;
            float ryz = dy * dy + dz * dz;
            if (!uAnisotropic && ryz >= h2)
                continue;
            vec4 g1 = sKernel[3u * m + 1u];
            vec4 g2 = sKernel[3u * m + 2u];
            mat3 gm = mat3(g1.x, g1.y, g1.z, g1.y, g1.w, g2.x, g1.z, g2.x, g2.y);
            for (int x = 0; x < int(kSurfaceBlockSide); ++x) {
                float dx = uOrigin.x + float(first.x + x) * uCell - p.x;
                float q;
                if (uAnisotropic) {
                    vec3 u = gm * vec3(dx, dy, dz);
                    q = h2 - dot(u, u);
                } else {
                    q = h2 - ryz - dx * dx;
                }
                if (q > 0.0)
                    acc[x] += uint(scale * q * q * q + 0.5);
            }
        }
        barrier(); // before the next round's list
    }
    uint base = slot * kSurfaceBlockSamples + 8u * row;
    for (uint x = 0u; x < kSurfaceBlockSide; ++x)
        field[base + x] = acc[x];
}
