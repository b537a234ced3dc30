// Layouts, bindings and constants of the GPU SDF bake (sdf_distance.comp, sdf_sign.comp).
// Shared by GLSL and C++ (bake/src/Bvh.cpp builds these structs, GpuBaker.cpp uploads them).
//
// Coordinates on the GPU are grid-relative and in voxels: (p - grid origin) / voxelSize, so grid
// point (i, j, k) sits exactly at (i, j, k) and float keeps ~1e-7 relative precision of numbers
// no larger than the grid, rather than of world coordinates far from the origin.
#ifndef SLUICE_SHARED_SDF_BAKE_H
#define SLUICE_SHARED_SDF_BAKE_H

#include "shared/GlslBridge.h"

SLUICE_SHARED_BEGIN

/// Local work-group size of both bake shaders [invocations]: 4 x 4 x 4 grid points, so one
/// group covers a compact block and its invocations walk similar BVH paths.
SLUICE_CONST int kBakeLocalSize = 4;

/// SSBO bindings.
SLUICE_CONST int kBakeNodesBinding = 0;     ///< BvhNode nodes[]
SLUICE_CONST int kBakeTrianglesBinding = 1; ///< BvhTriangle triangles[], in leaf order
SLUICE_CONST int kBakeDistanceBinding = 2;  ///< float phi[] per grid point, x fastest

/// Most triangles in a BVH leaf.
SLUICE_CONST int kBvhLeafSize = 4;

/// One BVH node, std430 (80 bytes). Nodes are stored in depth-first preorder, so the shaders walk
/// the tree without a stack: an internal node's first child is the next node, and `skip` is the
/// node after the whole subtree (the node count for the last subtree), where a walk goes on when
/// it is done with or prunes this node. Leaves own triangles [first, first + count).
struct BvhNode {
    vec4 boxMin;  ///< xyz: [voxels] box of the node's triangles; w unused
    vec4 boxMax;  ///< xyz: [voxels]; w unused
    vec4 center;  ///< xyz: area-weighted centroid of the triangles [voxels]; w: radius of the
                  ///< ball around it holding every corner [voxels]
    vec4 dipole;  ///< xyz: sum of area * unit normal over the triangles [voxels^2] (Barill et
                  ///< al. 2018, eq. 14, first-order term); w unused
    uint first;   ///< internal: index of the second child; leaf: first triangle
    uint count;   ///< 0 for internal nodes; otherwise the number of triangles (1..kBvhLeafSize)
    uint skip;    ///< the node after this subtree in preorder
    uint pad;
};

/// One triangle, corners in voxels relative to the grid origin, std430 (48 bytes). Winding order
/// as in the mesh (turned outward for closed meshes wound inward).
struct BvhTriangle {
    vec4 a; ///< xyz corner; w unused
    vec4 b;
    vec4 c;
};

SLUICE_SHARED_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(sluice::shared::BvhNode) == 80, "std430 size of BvhNode");
static_assert(offsetof(sluice::shared::BvhNode, center) == 32, "std430 offset of center");
static_assert(offsetof(sluice::shared::BvhNode, dipole) == 48, "std430 offset of dipole");
static_assert(offsetof(sluice::shared::BvhNode, first) == 64, "std430 offset of first");
static_assert(offsetof(sluice::shared::BvhNode, count) == 68, "std430 offset of count");
static_assert(offsetof(sluice::shared::BvhNode, skip) == 72, "std430 offset of skip");
static_assert(sizeof(sluice::shared::BvhTriangle) == 48, "std430 size of BvhTriangle");
static_assert(offsetof(sluice::shared::BvhTriangle, c) == 32, "std430 offset of c");
#endif

#endif // SLUICE_SHARED_SDF_BAKE_H
