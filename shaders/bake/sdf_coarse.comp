// Coarse distance pass: the nearest triangle of every coarse point (every 4th grid point along
// each axis, shared/SdfBake.h; SDF_SPARSE: those of each brick in the list; SDF_POINTS: each
// query point, for the sparse bake's culling), through the BVH. The fine pass starts its search
// from these triangles, and the coarse sign pass (sdf_sign.comp) gives the points their sign.
// Each invocation takes a block of 2 x 2 x 4 coarse points, walked together (walkBlock), as the
// fine pass does with grid points.
#version 450 core
#extension GL_ARB_shader_group_vote : enable

#include "glsl/SdfBakeGlsl.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kBakeLocalSize) in;

layout(std430, binding = kBakeCoarseBinding) writeonly buffer Coarse { CoarsePoint coarse[]; };

uniform uint bvhDepth; // levels below the root

// The link of the leaf reached from the root by always stepping into the child whose box is
// nearer p: a first bound for the walk. A for loop bounded by the tree depth.
uint greedyLeaf(vec3 p) {
    uint n = 0u;
    for (uint level = 0u; level < bvhDepth; ++level) {
        if (linkCount(texelFetch(distanceNodes, int(2u * n + 1u)).w) != 0u)
            break;
        // The first child is n + 1; the second starts where the first one's subtree ends.
        uvec4 firstLo = texelFetch(distanceNodes, int(2u * n + 2u));
        uvec4 firstHi = texelFetch(distanceNodes, int(2u * n + 3u));
        uint second = linkCount(firstHi.w) != 0u ? n + 2u : linkIndex(firstHi.w);
        uvec4 secondLo = texelFetch(distanceNodes, int(2u * second));
        uvec4 secondHi = texelFetch(distanceNodes, int(2u * second + 1u));
        float d1 = boxDistance2(p, uintBitsToFloat(firstLo.xyz), uintBitsToFloat(firstHi.xyz));
        float d2 = boxDistance2(p, uintBitsToFloat(secondLo.xyz), uintBitsToFloat(secondHi.xyz));
        n = d1 <= d2 ? n + 1u : second;
    }
    return texelFetch(distanceNodes, int(2u * n + 1u)).w;
}

#if defined(SDF_POINTS)
uniform uint itemCount; // query points in the list
#endif

void main() {
    float z[kBakeBlockDepth];
    vec4 best[kBakeBlockDepth]; // squared distances [voxels^2], layer by layer
    uvec4 nearest[kBakeBlockDepth];
    vec3 q0, q1;
#if defined(SDF_SPARSE)
    // Four invocations per brick, each a block of its coarse points (only real ones are written).
    uint brick;
    uvec3 c0;
    brickCoarseBlock(SLUICE_GLOBAL_ID.x, brick, c0, q0, q1, z);
#elif defined(SDF_POINTS)
    // One query point per invocation, as a block whose points all coincide.
    uint item = SLUICE_GLOBAL_ID.x;
    vec3 p = queryPoints[min(item, itemCount - 1u)].xyz;
    q0 = p;
    q1 = p;
    for (int j = 0; j < kBakeBlockDepth; ++j)
        z[j] = p.z;
#else
    uvec3 group = gl_WorkGroupID + SLUICE_GROUP_OFFSET_UNIFORM;
    uvec3 first = (group * 4u + mortonPosition(gl_LocalInvocationIndex)) * kBakeBlockSize;
    uvec3 cd = coarseDims();
    // Coarse points past the coarse grid search as clamped ones, so every lane runs the same
    // loops; only those on it write.
    q0 = vec3(coarseGridPoint(min(first, cd - 1u)));
    q1 = vec3(coarseGridPoint(min(first + 1u, cd - 1u)));
    for (int j = 0; j < kBakeBlockDepth; ++j)
        z[j] = float(coarseGridPoint(min(first + uvec3(0u, 0u, uint(j)), cd - 1u)).z);
#endif
    for (int j = 0; j < kBakeBlockDepth; ++j) {
        best[j] = vec4(3.0e38);
        nearest[j] = uvec4(0u);
    }
    uint leaf = greedyLeaf(0.5 * (q0 + vec3(q1.xy, z[kBakeBlockDepth - 1])));
    for (uint t = linkIndex(leaf); t < linkIndex(leaf) + linkCount(leaf); ++t)
        blockTriangle(t, q0, q1, z, best, nearest);
    walkBlock(q0, q1, z, best, nearest);

#if defined(SDF_SPARSE)
    for (int k = 0; k < 4 * kBakeBlockDepth; ++k) {
        if (brick < brickCount && blockCoarsePoint(c0, k))
            coarse[brickCoarseIndex(brick, c0 + blockPointOffset(k))] =
                CoarsePoint(sqrt(best[k >> 2][k & 3]), nearest[k >> 2][k & 3]);
    }
#elif defined(SDF_POINTS)
    if (item < itemCount)
        coarse[item] = CoarsePoint(sqrt(best[0][0]), nearest[0][0]);
#else
    for (int k = 0; k < 4 * kBakeBlockDepth; ++k) {
        uvec3 c = first + blockPointOffset(k);
        if (all(lessThan(c, cd)))
            coarse[c.x + cd.x * (c.y + cd.y * c.z)] =
                CoarsePoint(sqrt(best[k >> 2][k & 3]), nearest[k >> 2][k & 3]);
    }
#endif
}
