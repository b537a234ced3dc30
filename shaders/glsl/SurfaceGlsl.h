// GLSL side of the surface passes: the grid's uniforms, the buffers, the sample lookup through
// the block map, and the per-block passes' scan over a block's rows.
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

// Corner c of a cell (bit 0: +x, bit 1: +y, bit 2: +z).
ivec3 cornerOffset(uint c) {
    return ivec3(int(c & 1u), int((c >> 1u) & 1u), int((c >> 2u) & 1u));
}

// The trilinear weight of corner c of a cell for a point at fraction f of it.
float cornerWeight(vec3 f, uint c) {
    vec3 w = mix(1.0 - f, f, vec3(cornerOffset(c)));
    return w.x * w.y * w.z;
}

// The cell triangle table (runtime/src/surface/CubeTable.h): kSurfaceCellTrianglesMax entries
// per inside pattern, then each pattern's triangle count.
layout(std430, binding = kSurfBindTriangleTable) readonly buffer TriangleTable {
    uint triangleTable[];
};

uint cellTriangles(uint insideMask) {
    return triangleTable[256u * kSurfaceCellTrianglesMax + insideMask];
}

// The first sample of block b where it is stored, or 0xffffffff where it is not (or is past
// the grid).
uint storedBlockBase(ivec3 b) {
    if (any(lessThan(b, ivec3(0))) || any(greaterThanEqual(b, uBlocks)))
        return 0xffffffffu;
    uint index = blockIndex(b);
    return blockFlag[index] == 0u ? 0xffffffffu : blockSlot[index] * kSurfaceBlockSamples;
}

// The block offset (-1, 0 or 1) of local coordinate l in -8 .. 15.
int blockStep(int l) {
    return l < 0 ? -1 : (l >= int(kSurfaceBlockSide) ? 1 : 0);
}

// Work-group exclusive scan of one uint per row (kSurfaceBlockRows invocations); `total` gets
// the sum. The first invocation adds them up in turn between two barriers (software GL runs
// the group's invocations as a handful of vectors: one short loop beats every invocation
// reading every row). Every invocation must call it.
shared uint scanRow[kSurfaceBlockRows + 1u];

uint rowExclusiveScan(uint row, uint value, out uint total) {
    scanRow[row] = value;
    barrier();
    if (row == 0u) {
        uint sum = 0u;
        for (uint i = 0u; i < kSurfaceBlockRows; ++i) {
            uint v = scanRow[i];
            scanRow[i] = sum;
            sum += v;
        }
        scanRow[kSurfaceBlockRows] = sum;
    }
    barrier();
    total = scanRow[kSurfaceBlockRows];
    return scanRow[row];
}

#endif // SLUICE_SHARED_SURFACE_GLSL_H
