// Fine distance pass over a z-slab of work groups (SDF_SPARSE: a range of the brick list, two
// bricks per work group): the exact unsigned distance of every grid point, and its sign wherever
// a coarse point's empty ball covers it; blocks with other points are appended to the pending
// list for sdf_sign.comp. Coordinates are grid-relative voxels (shared/SdfBake.h).
//
// Each invocation owns a block of 2 x 2 x 4 grid points: it fetches every node and triangle once
// for its 16 points (loads are what llvmpipe pays for most), tests node boxes against each
// point's own best distance (walkBlock, glsl/SdfBakeGlsl.h), and starts from the nearest
// triangles of the 8 coarse points around the block.
#version 450 core
#extension GL_ARB_shader_group_vote : enable

#include "glsl/SdfBakeGlsl.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kBakeLocalSize) in;

layout(std430, binding = kBakeDistanceBinding) writeonly buffer Distances { float phi[]; };
layout(std430, binding = kBakeCoarseBinding) readonly buffer Coarse { CoarsePoint coarse[]; };
layout(std430, binding = kBakePendingBinding) buffer Pending {
    PendingHeader pending;
    uvec2 pendingBlocks[]; // (block index, mask of its pending points)
};

uniform uint groupBegin; // first z work group of this slab (SDF_SPARSE: first x work group)
uniform uint propagate;  // 1: take the sign of a covering coarse point (the winding number is an
                         // integer off the surface); 0: every point is pending

const int kDepth = kBakeBlockDepth;
const int kPoints = 4 * kDepth;

// The coarse entry and grid point of corner s (0..7) of the coarse cell holding the block at
// `origin` (blocks are aligned, so a block never straddles two cells).
void cellCorner(uvec3 origin, uint brick, int s, out uint index, out vec3 point) {
    uvec3 offset = uvec3(s & 1, (s >> 1) & 1, s >> 2);
#if defined(SDF_SPARSE)
    uvec3 c = (origin - brickOrigin(brick)) / uint(kBakeCoarseSpacing) + offset;
    index = coarseRep[brickCoarseIndex(brick, c)];
    point = vec3(brickCoarsePoint(brick, c));
#else
    uvec3 cd = coarseDims();
    uvec3 c = min(min(origin, dims - 1u) / uint(kBakeCoarseSpacing) + offset, cd - 1u);
    index = c.x + cd.x * (c.y + cd.y * c.z);
    point = vec3(coarseGridPoint(c));
#endif
}

// The block's signed distances [voxels] from its nearest squared distances `best`, and the mask
// of its points whose sign is still unknown (for the sign pass). Inside the open ball of radius
// |phi(c)| around a coarse point c there is no surface, and the winding number of a closed
// surface only changes across it, so a point in the ball has c's sign. The margin keeps float
// rounding of phi(c) on the safe side. (The corners are read only here, after the walk, so the
// walk needs fewer registers.)
uint signBlock(uvec3 origin, uint brick, bool live, vec3 q0, vec3 q1, float z[kDepth],
               vec4 best[kDepth], out float signedDistance[kPoints]) {
    vec3 cornerPoint[8];
    float cornerDistance[8]; // signed [voxels]
    for (int s = 0; s < 8; ++s) {
        uint index;
        cellCorner(origin, brick, s, index, cornerPoint[s]);
        cornerDistance[s] = coarse[index].distance;
    }
    uint pendingMask = 0u;
    for (int k = 0; k < kPoints; ++k) {
        uvec3 id = origin + blockPointOffset(k);
        float d = sqrt(best[k >> 2][k & 3]);
        vec3 p = layerPoint(q0, q1, z[k >> 2], k & 3);
        float sign = 0.0;
        for (int s = 0; s < 8; ++s) {
            float radius = abs(cornerDistance[s]) * (1.0 - 1.0e-5) - 1.0e-3;
            vec3 r = p - cornerPoint[s];
            bool covered = propagate != 0u && radius > 0.0 && dot(r, r) < radius * radius;
            sign = sign == 0.0 && covered ? (cornerDistance[s] < 0.0 ? -1.0 : 1.0) : sign;
        }
        bool onGrid = live && all(lessThan(id, dims));
        pendingMask |= onGrid && d > 0.0 && sign == 0.0 ? 1u << k : 0u;
        signedDistance[k] = sign < 0.0 ? -d : d;
    }
    return pendingMask;
}

void main() {
#if defined(SDF_SPARSE)
    // Work groups along x over the list, two bricks each; the entry is the block's slot.
    uint group = gl_WorkGroupID.x + SLUICE_GROUP_OFFSET_UNIFORM.x + groupBegin;
    uint entry = group * gl_WorkGroupSize.x + gl_LocalInvocationIndex;
    uint brick = entry / kBrickBlocks;
    bool live = brick < brickCount;
    uvec3 origin = slotOrigin(entry);
#else
    uvec3 group = gl_WorkGroupID + SLUICE_GROUP_OFFSET_UNIFORM + uvec3(0u, 0u, groupBegin);
    uvec3 blockInGroup = mortonPosition(gl_LocalInvocationIndex);
    uvec3 origin = (group * 4u + blockInGroup) * kBakeBlockSize;
    uint brick = 0u;
    bool live = true;
    uvec3 bd = blockDims(), bi = origin / kBakeBlockSize;
    uint entry = bi.x + bd.x * (bi.y + bd.y * bi.z);
#endif
    vec3 q0, q1;
    float z[kDepth];
    blockPoints(origin, q0, q1, z);
    // Points past the grid search as clamped points, so every lane runs the same loops.
    vec4 best[kDepth]; // squared distances [voxels^2], layer by layer
    uvec4 nearest[kDepth]; // unused here
    for (int j = 0; j < kDepth; ++j) {
        best[j] = vec4(3.0e38);
        nearest[j] = uvec4(0u);
    }

    // First bound: the nearest triangles of the coarse points at the corners of the coarse cell
    // holding the block (blocks are aligned, so a block never straddles two cells); then the walk
    // prunes almost as well as one that knew the answer.
    for (int s = 0; s < 8; ++s) {
        uint index;
        vec3 point;
        cellCorner(origin, brick, s, index, point);
        blockTriangle(coarse[index].triangle, q0, q1, z, best, nearest);
    }
    walkBlock(q0, q1, z, best, nearest);

    float signedDistance[kPoints];
    uint pendingMask = signBlock(origin, brick, live, q0, q1, z, best, signedDistance);
    // Stores after the loops above (llvmpipe runs them much faster that way). A sparse brick
    // stores its points past the grid too (the clamped ones' values); nobody reads them.
    for (int k = 0; k < kPoints; ++k) {
#if defined(SDF_SPARSE)
        if (live)
            phi[blockPointIndex(entry, origin, k)] = signedDistance[k];
#else
        uvec3 id = origin + blockPointOffset(k);
        if (all(lessThan(id, dims)))
            phi[gridIndex(id)] = signedDistance[k];
#endif
    }
    atomicAdd(pending.points, uint(bitCount(pendingMask)));
    uint slot = atomicAdd(pending.count, pendingMask != 0u ? 1u : 0u);
    if (pendingMask != 0u)
        pendingBlocks[slot] = uvec2(entry, pendingMask);
}
