// Per stored block: the vertices its samples own (crossing edges) and the triangles of the
// cells whose lowest corner it holds; and each sample's code (its crossing edges and its
// cell's inside corners) for the passes that write them. One invocation per row of samples.
// A code needs only which samples are inside, for the block's samples and those one step up
// along x, y and z: the 9 x 9 rows of 9 samples (local 0 .. 8) are read once into bit masks.
#version 450 core

#include "glsl/SurfaceGlsl.h"

layout(local_size_x = kSurfaceBlockRows) in;

layout(std430, binding = kSurfBindBlockVerts) writeonly buffer BlockVerts { uint blockVerts[]; };
layout(std430, binding = kSurfBindBlockTris) writeonly buffer BlockTris { uint blockTris[]; };
layout(std430, binding = kSurfBindSampleCode) writeonly buffer SampleCode { uint sampleCode[]; };

const uint kRows = kSurfaceBlockSide + 1u; // rows (and samples a row) of the masks

// Which samples of row (local 0 .. 8, y, z) are inside, bit x for local x.
shared uint insideRow[kRows * kRows];
shared uint groupVerts;
shared uint groupTris;

// The inside bits of the row (0 .. 8, y, z) of the block at `origin` (local y, z in 0 .. 8): its
// first 8 samples in the block `b` holds (the block itself, or the one after it along y or z),
// the ninth in the block after that along x.
uint rowInsideBits(ivec3 origin, ivec3 b, int y, int z) {
    int side = int(kSurfaceBlockSide);
    ivec3 s = origin + ivec3(0, y, z);
    if (s.y >= uSamples.y || s.z >= uSamples.z)
        return 0u;
    uint within = laneOf(ivec3(0, y % side, z % side));
    uint bits = 0u;
    uint base = storedBlockBase(b);
    if (base != 0xffffffffu)
        for (int x = 0; x < side; ++x)
            if (s.x + x < uSamples.x && field[base + within + uint(x)] > uIsoFixed)
                bits |= 1u << uint(x);
    uint next = storedBlockBase(b + ivec3(1, 0, 0));
    if (next != 0xffffffffu && s.x + side < uSamples.x && field[next + within] > uIsoFixed)
        bits |= 1u << uint(side);
    return bits;
}

// The code of sample (x, y, z) from the inside bits of rows (y, z), (y + 1, z), (y, z + 1) and
// (y + 1, z + 1): its crossing edges along +x, +y and +z (bits 0, 1 and 3: bit d - 1 for the
// corner offset d) and, from bit 8, the inside corners of the cell it is the lowest corner of
// (bit c for corner c).
uint sampleCodeOf(uint x, uint here, uint up, uint front, uint both) {
    uint inside = (here >> x) & 1u;
    uint edges = (inside ^ ((here >> (x + 1u)) & 1u)) | ((inside ^ ((up >> x) & 1u)) << 1u) |
                 ((inside ^ ((front >> x) & 1u)) << 3u);
    uint cell = ((here >> x) & 3u) | (((up >> x) & 3u) << 2u) | (((front >> x) & 3u) << 4u) |
                (((both >> x) & 3u) << 6u);
    return edges | (cell << 8u);
}

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockRows;
    uint row = gl_LocalInvocationID.x;
    if (slot >= uCount) // uniform over the group
        return;
    if (row == 0u) {
        groupVerts = 0u;
        groupTris = 0u;
    }
    ivec3 block = blockCoord(activeBlock[slot]);
    ivec3 origin = block * int(kSurfaceBlockSide);
    int side = int(kSurfaceBlockSide);
    int y = int(row % kSurfaceBlockSide);
    int z = int(row / kSurfaceBlockSide);
    insideRow[uint(y) + kRows * uint(z)] = rowInsideBits(origin, block, y, z);
    // The rows past the block along y (z = 0 .. 7), along z (y = 0 .. 7), and along both.
    if (row < 2u * kSurfaceBlockSide + 1u) {
        int k = int(row);
        ivec3 at = k < side ? ivec3(0, side, k) : (k < 2 * side ? ivec3(0, k - side, side)
                                                                : ivec3(0, side, side));
        ivec3 b = block + ivec3(0, at.y / side, at.z / side);
        insideRow[uint(at.y) + kRows * uint(at.z)] = rowInsideBits(origin, b, at.y, at.z);
    }
    barrier(); // also publishes the zeroed sums
    uint verts = 0u;
    uint tris = 0u;
    uint here = insideRow[uint(y) + kRows * uint(z)];
    uint up = insideRow[uint(y + 1) + kRows * uint(z)];
    uint front = insideRow[uint(y) + kRows * uint(z + 1)];
    uint both = insideRow[uint(y + 1) + kRows * uint(z + 1)];
    bool rowInGrid = origin.y + y < uSamples.y && origin.z + z < uSamples.z;
    for (int x = 0; x < side; ++x) {
        uint code = 0u;
        if (rowInGrid && origin.x + x < uSamples.x) {
            code = sampleCodeOf(uint(x), here, up, front, both);
            uint cell = code >> 8u;
            verts += bitCount(code & 0x7fu);
            tris += cell == 0u || cell == 0xffu ? 0u : cellTriangles(cell);
        }
        sampleCode[slot * kSurfaceBlockSamples + row * kSurfaceBlockSide + uint(x)] = code;
    }
    if (verts != 0u)
        atomicAdd(groupVerts, verts);
    if (tris != 0u)
        atomicAdd(groupTris, tris);
    barrier();
    if (row == 0u) {
        blockVerts[slot] = groupVerts;
        blockTris[slot] = groupTris;
    }
}
