// Per stored block: the triangles of each cell whose lowest corner it holds (marching cubes,
// the cell triangle table), at its block's base plus a scan over its rows, in a fixed order.
// One invocation per row of samples counts and numbers the triangles; then the block's
// triangles, listed in shared memory, are shared out one per invocation. A vertex is found by
// the edge it lies on. Each triangle faces out of the fluid (down the field).
#version 450 core

#include "glsl/SurfaceGlsl.h"

layout(local_size_x = kSurfaceBlockRows) in;

layout(std430, binding = kSurfBindBlockTris) readonly buffer BlockTris { uint blockTris[]; };
layout(std430, binding = kSurfBindTriBase) readonly buffer TriBase { uint triBase[]; };
layout(std430, binding = kSurfBindSampleVert) readonly buffer SampleVert { uint sampleVert[]; };
layout(std430, binding = kSurfBindSampleCode) readonly buffer SampleCode { uint sampleCode[]; };
layout(std430, binding = kSurfBindTriangles) writeonly buffer Triangles { uint triangles[]; };

uint gSlot;     // the block's slot
ivec3 gLocal;  // the cell's lowest corner in the block

// The vertex on the edge between cell corners a and b (one holds the other's bits): its owner
// (the lower end) keeps its first vertex and its crossing edges; an owner in this block is
// found without the block map.
uint edgeVertex(ivec3 s, uint a, uint b) {
    uint lo = bitCount(a) < bitCount(b) ? a : b;
    uint d = a ^ b;
    ivec3 local = gLocal + cornerOffset(lo);
    uint owner = all(lessThan(local, ivec3(int(kSurfaceBlockSide))))
                     ? gSlot * kSurfaceBlockSamples + laneOf(local)
                     : sampleSlot(s + cornerOffset(lo));
    uint edges = sampleCode[owner] & 0x7fu;
    return sampleVert[owner] + bitCount(edges & ((1u << (d - 1u)) - 1u));
}

// The vertex on an edge as the table codes it: lower corner (bits 0-2), offset (bits 3-5).
uint codedVertex(ivec3 s, uint edge) {
    uint lo = edge & 7u;
    return edgeVertex(s, lo, lo | (edge >> 3u));
}

// The block's triangles in order: the index in the block of the cell's lowest corner (bits
// 0-8), the cell's inside corners (bits 9-16) and the triangle's place in the cell's table
// entry (from 17).
shared uint blockTriangles[kSurfaceCellTrianglesMax * kSurfaceBlockSamples];

// Triangle k of the cell at s (lowest corner, gLocal in the block) whose inside corners are
// `inside`, written at triangle `at`, from the cell triangle table
// (runtime/src/surface/CubeTable.h: each triangle facing out of the fluid).
void emitTriangle(uint at, ivec3 s, uint inside, uint k) {
    uint t = triangleTable[inside * kSurfaceCellTrianglesMax + k];
    triangles[3u * at] = codedVertex(s, t & 63u);
    triangles[3u * at + 1u] = codedVertex(s, (t >> 6u) & 63u);
    triangles[3u * at + 2u] = codedVertex(s, (t >> 12u) & 63u);
}

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockRows;
    uint row = gl_LocalInvocationID.x;
    if (slot >= uCount || blockTris[slot] == 0u) // uniform over the group
        return;
    ivec3 origin = blockCoord(activeBlock[slot]) * int(kSurfaceBlockSide);
    uint first = slot * kSurfaceBlockSamples + row * kSurfaceBlockSide;
    // The row's triangles, numbered over the rows in one scan, then listed one entry each and
    // shared out one per invocation.
    uint inside[kSurfaceBlockSide];
    uint counts[kSurfaceBlockSide];
    uint mine = 0u;
    for (uint x = 0u; x < kSurfaceBlockSide; ++x) {
        inside[x] = sampleCode[first + x] >> 8u;
        counts[x] = cellTriangles(inside[x]);
        mine += counts[x];
    }
    uint total;
    uint triangle = rowExclusiveScan(row, mine, total);
    for (uint x = 0u; x < kSurfaceBlockSide; ++x)
        for (uint k = 0u; k < counts[x]; ++k)
            blockTriangles[triangle++] = (row * kSurfaceBlockSide + x) | (inside[x] << 9u) |
                                         (k << 17u);
    barrier();
    gSlot = slot;
    uint base = triBase[slot];
    for (uint i = row; i < total; i += kSurfaceBlockRows) {
        uint entry = blockTriangles[i];
        gLocal = laneCoord(entry & 511u);
        emitTriangle(base + i, origin + gLocal, (entry >> 9u) & 255u, entry >> 17u);
    }
}
