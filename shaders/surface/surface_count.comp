// Per stored block: the vertices its samples own (crossing edges) and the triangles of the
// cells whose lowest corner it holds; and each sample's code (its crossing edges and its
// cell's inside corners) for the passes that write them. One invocation per row of samples.
#version 450 core

#include "shared/SurfaceGlsl.h"

layout(local_size_x = kSurfaceBlockRows) in;

layout(std430, binding = kSurfBindBlockVerts) writeonly buffer BlockVerts { uint blockVerts[]; };
layout(std430, binding = kSurfBindBlockTris) writeonly buffer BlockTris { uint blockTris[]; };
layout(std430, binding = kSurfBindSampleCode) writeonly buffer SampleCode { uint sampleCode[]; };

shared uint groupVerts;
shared uint groupTris;

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockRows;
    uint row = gl_LocalInvocationID.x;
    if (slot >= uCount) // uniform over the group
        return;
    if (row == 0u) {
        groupVerts = 0u;
        groupTris = 0u;
    }
    ivec3 origin = blockCoord(activeBlock[slot]) * int(kSurfaceBlockSide);
    loadTile(origin, row); // its barrier also publishes the zeroed sums
    uint verts = 0u;
    uint tris = 0u;
    int y = int(row % kSurfaceBlockSide);
    int z = int(row / kSurfaceBlockSide);
    uint here = tileInsideBits(y, z);
    uint up = tileInsideBits(y + 1, z);
    uint front = tileInsideBits(y, z + 1);
    uint both = tileInsideBits(y + 1, z + 1);
    bool rowInGrid = origin.y + y < uSamples.y && origin.z + z < uSamples.z;
    for (int x = 0; x < int(kSurfaceBlockSide); ++x) {
        uint code = 0u;
        if (rowInGrid && origin.x + x < uSamples.x) {
            code = tileSampleCode(x, here, up, front, both);
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
