// Per stored block: the vertices its samples own (crossing edges) and the triangles of the
// cells whose lowest corner it holds.
#version 450 core

#include "shared/SurfaceGlsl.h"

layout(local_size_x = kSurfaceBlockSamples) in;

layout(std430, binding = kSurfBindBlockVerts) writeonly buffer BlockVerts { uint blockVerts[]; };
layout(std430, binding = kSurfBindBlockTris) writeonly buffer BlockTris { uint blockTris[]; };

shared uint groupVerts;
shared uint groupTris;

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockSamples;
    uint lane = gl_LocalInvocationID.x;
    if (lane == 0u) {
        groupVerts = 0u;
        groupTris = 0u;
    }
    barrier();
    if (slot < uCount) { // uniform over the group
        ivec3 s = blockCoord(activeBlock[slot]) * int(kSurfaceBlockSide) + laneCoord(lane);
        if (all(lessThan(s, uSamples))) {
            atomicAdd(groupVerts, bitCount(crossingEdges(s)));
            atomicAdd(groupTris, cellTriangles(cellInsideMask(s)));
        }
    }
    barrier();
    if (lane == 0u && slot < uCount) {
        blockVerts[slot] = groupVerts;
        blockTris[slot] = groupTris;
    }
}
