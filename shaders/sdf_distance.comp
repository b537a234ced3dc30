// Fine distance pass over a z-slab of work groups: the exact unsigned distance of every grid
// point, and its sign wherever a coarse point's empty ball covers it; blocks with other points
// are appended to the pending list for sdf_sign.comp. Coordinates are grid-relative voxels
// (shared/SdfBake.h).
//
// Each invocation owns a block of 2 x 2 x 4 grid points: it fetches every node and triangle once
// for its 16 points (loads are what llvmpipe pays for most), tests node boxes against each
// point's own best distance (walkBlock, shared/SdfBakeGlsl.h), and starts from the nearest
// triangles of the 8 coarse points around the block.
#version 450 core
#extension GL_ARB_shader_group_vote : enable

#include "shared/SdfBakeGlsl.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kBakeLocalSize) in;

layout(std430, binding = kBakeDistanceBinding) writeonly buffer Distances { float phi[]; };
layout(std430, binding = kBakeCoarseBinding) readonly buffer Coarse { CoarsePoint coarse[]; };
layout(std430, binding = kBakePendingBinding) buffer Pending {
    PendingHeader pending;
    uvec2 pendingBlocks[]; // (block index, mask of its pending points)
};

uniform uint groupBegin; // first z work group of this slab
uniform uint propagate;  // 1: take the sign of a covering coarse point (the winding number is an
                         // integer off the surface); 0: every point is pending

const int kDepth = kBakeBlockDepth;
const int kPoints = 4 * kDepth;

void main() {
    uvec3 group = gl_WorkGroupID + SLUICE_GROUP_OFFSET_UNIFORM + uvec3(0u, 0u, groupBegin);
    uvec3 blockInGroup = mortonPosition(gl_LocalInvocationIndex);
    uvec3 origin = (group * 4u + blockInGroup) * kBakeBlockSize;
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
    uvec3 cd = coarseDims();
    uvec3 cell = min(origin, dims - 1u) / uint(kBakeCoarseSpacing);
    for (int s = 0; s < 8; ++s) {
        uvec3 cc = min(cell + uvec3(s & 1, (s >> 1) & 1, s >> 2), cd - 1u);
        blockTriangle(coarse[cc.x + cd.x * (cc.y + cd.y * cc.z)].triangle, q0, q1, z, best,
                      nearest);
    }
    walkBlock(q0, q1, z, best, nearest);

    // Sign: inside the open ball of radius |phi(c)| around a coarse point c there is no surface,
    // and the winding number of a closed surface only changes across it, so a point in the ball
    // has c's sign. The margin keeps float rounding of phi(c) on the safe side. (Read only now,
    // so the walk above needs fewer registers.)
    vec3 cornerPoint[8];
    float cornerDistance[8]; // signed [voxels]
    for (int s = 0; s < 8; ++s) {
        uvec3 cc = min(cell + uvec3(s & 1, (s >> 1) & 1, s >> 2), cd - 1u);
        cornerPoint[s] = vec3(coarseGridPoint(cc));
        cornerDistance[s] = coarse[cc.x + cd.x * (cc.y + cd.y * cc.z)].distance;
    }
    uint pendingMask = 0u;
    float signedDistance[kPoints];
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
        bool onGrid = all(lessThan(id, dims));
        pendingMask |= onGrid && d > 0.0 && sign == 0.0 ? 1u << k : 0u;
        signedDistance[k] = sign < 0.0 ? -d : d;
    }
    // Stores after the loops above (llvmpipe runs them much faster that way).
    for (int k = 0; k < kPoints; ++k) {
        uvec3 id = origin + blockPointOffset(k);
        if (all(lessThan(id, dims)))
            phi[gridIndex(id)] = signedDistance[k];
    }
    atomicAdd(pending.points, uint(bitCount(pendingMask)));
    uint slot = atomicAdd(pending.count, pendingMask != 0u ? 1u : 0u);
    uvec3 bd = blockDims(), bi = origin / kBakeBlockSize;
    if (pendingMask != 0u)
        pendingBlocks[slot] = uvec2(bi.x + bd.x * (bi.y + bd.y * bi.z), pendingMask);
}
