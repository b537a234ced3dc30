// GLSL side of the surface passes: the grid's uniforms, the buffers, and the sample lookup
// through the block map (0 outside the stored blocks).
#ifndef SLUICE_SHARED_SURFACE_GLSL_H
#define SLUICE_SHARED_SURFACE_GLSL_H

#include "shared/ChunkedDispatch.h"
#include "shared/Surface.h"

uniform vec3 uOrigin;    // world position of sample (0, 0, 0) [m]
uniform float uCell;     // sample spacing [m]
uniform ivec3 uSamples;  // samples along each axis
uniform ivec3 uBlocks;   // blocks along each axis
uniform uint uCount;     // particles, or stored blocks in the per-block passes
uniform float uSupport;  // kernel support radius [m]
uniform float uVolume;   // particle volume [m^3]
uniform uint uIsoFixed;  // iso value in field units, an odd multiple of 1/2 (never a sum)

layout(std430, binding = kSurfBindBlockFlag) buffer BlockFlag { uint blockFlag[]; };
layout(std430, binding = kSurfBindBlockSlot) buffer BlockSlot { uint blockSlot[]; };
layout(std430, binding = kSurfBindActive) buffer Active { uint activeBlock[]; };
layout(std430, binding = kSurfBindField) buffer Field { uint field[]; };

uint blockIndex(ivec3 b) {
    return uint(b.x) + uint(uBlocks.x) * (uint(b.y) + uint(uBlocks.y) * uint(b.z));
}

ivec3 blockCoord(uint index) {
    uint bx = uint(uBlocks.x);
    uint by = uint(uBlocks.y);
    return ivec3(int(index % bx), int((index / bx) % by), int(index / (bx * by)));
}

// The block holding world position p (clamped to the grid, which holds every particle).
ivec3 blockOfPoint(vec3 p) {
    ivec3 s = ivec3(floor((p - uOrigin) / uCell));
    return clamp(s / int(kSurfaceBlockSide), ivec3(0), uBlocks - 1);
}

// A particle's kernel (surface_anisotropy.comp; the sphere of radius uSupport round the
// particle when the kernels are isotropic): centre, the symmetric matrix G taking an offset
// from the centre to the sphere's scale (the field is poly6 of |G d|; det G = 1, so the kernel
// holds the sphere's volume), and the half-extents of the ellipsoid |G d| < uSupport.
struct SurfaceKernel {
    vec3 centre;
    mat3 g;
    vec3 extent;
};

SurfaceKernel packedKernel(vec4 a, vec4 b, vec4 c, vec4 d) {
    SurfaceKernel k;
    k.centre = a.xyz;
    k.g = mat3(b.x, b.y, b.z, b.y, b.w, c.x, b.z, c.x, c.y);
    k.extent = d.xyz;
    return k;
}

// The local sample of index i in a block (x fastest).
ivec3 laneCoord(uint i) {
    return ivec3(int(i & 7u), int((i >> 3u) & 7u), int(i >> 6u));
}

uint laneOf(ivec3 local) {
    return uint(local.x) + 8u * (uint(local.y) + 8u * uint(local.z));
}

// Where sample s is stored, or 0xffffffff where it is not (outside the grid or its block).
uint sampleSlot(ivec3 s) {
    if (any(lessThan(s, ivec3(0))) || any(greaterThanEqual(s, uSamples)))
        return 0xffffffffu;
    ivec3 b = s / int(kSurfaceBlockSide);
    uint index = blockIndex(b);
    if (blockFlag[index] == 0u)
        return 0xffffffffu;
    return blockSlot[index] * kSurfaceBlockSamples + laneOf(s - b * int(kSurfaceBlockSide));
}

uint sampleValue(ivec3 s) {
    uint slot = sampleSlot(s);
    return slot == 0xffffffffu ? 0u : field[slot];
}

// Corner c of a cell (bit 0: +x, bit 1: +y, bit 2: +z).
ivec3 cornerOffset(uint c) {
    return ivec3(int(c & 1u), int((c >> 1u) & 1u), int((c >> 2u) & 1u));
}

// Triangles of the cell whose lowest corner is s: over its six Kuhn tetrahedra (0, e_a,
// e_a + e_b, 7 for every order a, b, c of the axes), one for a tetrahedron with one or three
// corners inside, two for one with two.
const uint kTetCorners[24] = uint[24](0u, 1u, 3u, 7u,  0u, 1u, 5u, 7u,  0u, 2u, 3u, 7u,
                                      0u, 2u, 6u, 7u,  0u, 4u, 5u, 7u,  0u, 4u, 6u, 7u);

uint cellTriangles(uint insideMask) {
    uint count = 0u;
    for (uint t = 0u; t < 6u; ++t) {
        uint k = 0u;
        for (uint v = 0u; v < 4u; ++v)
            k += (insideMask >> kTetCorners[4u * t + v]) & 1u;
        count += k == 2u ? 2u : (k == 1u || k == 3u ? 1u : 0u);
    }
    return count;
}

// The per-block passes read a block's samples and a border around them from shared memory:
// local coordinates -1 .. 9 on each axis (the cells' +1 corners and the gradients' +-1 reach),
// loaded once per block instead of looked up through the block map for every use.
const int kTileSide = 11;
shared uint tile[kTileSide * kTileSide * kTileSide];

void loadTile(ivec3 blockOrigin, uint lane) {
    for (uint i = lane; i < uint(kTileSide * kTileSide * kTileSide); i += kSurfaceBlockRows) {
        ivec3 local = ivec3(int(i % uint(kTileSide)), int((i / uint(kTileSide)) % uint(kTileSide)),
                            int(i / uint(kTileSide * kTileSide))) - 1;
        tile[i] = sampleValue(blockOrigin + local);
    }
    barrier();
}

uint tileValue(ivec3 local) {
    ivec3 t = local + 1;
    return tile[t.x + kTileSide * (t.y + kTileSide * t.z)];
}

bool tileInside(ivec3 local) {
    return tileValue(local) > uIsoFixed;
}

// crossingEdges and cellInsideMask of the sample at `local` in the loaded tile.
uint tileCrossingEdges(ivec3 local) {
    bool inside = tileInside(local);
    uint mask = 0u;
    for (uint d = 1u; d < 8u; ++d)
        if (tileInside(local + cornerOffset(d)) != inside)
            mask |= 1u << (d - 1u);
    return mask;
}

uint tileCellInsideMask(ivec3 local) {
    uint mask = 0u;
    for (uint c = 0u; c < 8u; ++c)
        if (tileInside(local + cornerOffset(c)))
            mask |= 1u << c;
    return mask;
}

// Work-group exclusive scan of one uint per row (kSurfaceBlockRows invocations); `total` gets
// the sum. One barrier; each invocation adds the rows before its own. Every invocation must
// call it.
shared uint scanRow[kSurfaceBlockRows];

uint rowExclusiveScan(uint row, uint value, out uint total) {
    scanRow[row] = value;
    barrier();
    uint before = 0u;
    total = 0u;
    for (uint i = 0u; i < kSurfaceBlockRows; ++i) {
        uint v = scanRow[i];
        before += i < row ? v : 0u;
        total += v;
    }
    return before;
}

#endif // SLUICE_SHARED_SURFACE_GLSL_H
