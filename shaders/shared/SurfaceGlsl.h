// GLSL side of the surface passes: the grid's uniforms, the buffers, the sample lookup through
// the block map, and the per-block shared tile.
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

// The per-block passes read a block's samples and a border around them from shared memory:
// local coordinates -1 .. 9 on each axis (the cells' +1 corners and the gradients' +-1 reach),
// loaded once per block instead of looked up through the block map for every use; and, per
// row of the tile along x, which of its samples are inside (bit tx).
const int kTileSide = 11;
shared uint tile[kTileSide * kTileSide * kTileSide];
shared uint tileInsideRow[kTileSide * kTileSide];

// The first sample of block b where it is stored, or 0xffffffff where it is not (or is past
// the grid).
uint storedBlockBase(ivec3 b) {
    if (any(lessThan(b, ivec3(0))) || any(greaterThanEqual(b, uBlocks)))
        return 0xffffffffu;
    uint index = blockIndex(b);
    return blockFlag[index] == 0u ? 0xffffffffu : blockSlot[index] * kSurfaceBlockSamples;
}

// The block offset (-1, 0 or 1) of local coordinate l in -1 .. 9.
int blockStep(int l) {
    return l < 0 ? -1 : (l >= int(kSurfaceBlockSide) ? 1 : 0);
}

// A row of the tile along x, tile row r = ty + kTileSide tz: its three blocks looked up once,
// not once per sample.
void loadTileRow(ivec3 blockOrigin, uint r) {
    int side = int(kSurfaceBlockSide);
    ivec3 l = ivec3(-1, int(r % uint(kTileSide)) - 1, int(r / uint(kTileSide)) - 1);
    ivec3 b = blockOrigin / side + ivec3(0, blockStep(l.y), blockStep(l.z));
    ivec3 s = blockOrigin + l;
    bool rowInGrid = s.y >= 0 && s.y < uSamples.y && s.z >= 0 && s.z < uSamples.z;
    uint below = storedBlockBase(b - ivec3(1, 0, 0));
    uint here = storedBlockBase(b);
    uint above = storedBlockBase(b + ivec3(1, 0, 0));
    uint within = laneOf(ivec3(0, l.y - side * blockStep(l.y), l.z - side * blockStep(l.z)));
    uint inside = 0u;
    for (int tx = 0; tx < kTileSide; ++tx) {
        int x = tx - 1;
        int step = blockStep(x);
        uint base = step < 0 ? below : (step > 0 ? above : here);
        int sx = blockOrigin.x + x;
        uint value = 0u;
        if (rowInGrid && base != 0xffffffffu && sx >= 0 && sx < uSamples.x)
            value = field[base + within + uint(x - side * step)];
        tile[uint(tx) + uint(kTileSide) * r] = value;
        inside |= value > uIsoFixed ? 1u << uint(tx) : 0u;
    }
    tileInsideRow[r] = inside;
}

void loadTile(ivec3 blockOrigin, uint lane) {
    for (uint r = lane; r < uint(kTileSide * kTileSide); r += kSurfaceBlockRows)
        loadTileRow(blockOrigin, r);
    barrier();
}

uint tileValue(ivec3 local) {
    ivec3 t = local + 1;
    return tile[t.x + kTileSide * (t.y + kTileSide * t.z)];
}

// The inside bits of the tile's row through local (0, y, z), bit x + 1 for local x.
uint tileInsideBits(int y, int z) {
    return tileInsideRow[(y + 1) + kTileSide * (z + 1)];
}

// The codes of the row of samples (0 .. 7, y, z) of the loaded tile, from its inside bits:
// for sample x, its crossing edges along +x, +y and +z (bits 0, 1 and 3: bit d - 1 for the
// corner offset d) and, from bit 8, the inside corners of the cell it is the lowest corner of
// (bit c for corner c).
uint tileSampleCode(int x, uint here, uint up, uint front, uint both) {
    uint tx = uint(x + 1);
    uint inside = (here >> tx) & 1u;
    uint edges = (inside ^ ((here >> (tx + 1u)) & 1u)) | ((inside ^ ((up >> tx) & 1u)) << 1u) |
                 ((inside ^ ((front >> tx) & 1u)) << 3u);
    uint cell = ((here >> tx) & 3u) | (((up >> tx) & 3u) << 2u) | (((front >> tx) & 3u) << 4u) |
                (((both >> tx) & 3u) << 6u);
    return edges | (cell << 8u);
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
