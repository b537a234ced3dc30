// Layouts, bindings and constants of the GPU SDF bake (shaders/sdf_*.comp, glsl/SdfBakeGlsl.h).
// Shared by GLSL and C++ (bake/src/gpu/Bvh.cpp builds the texel arrays, GpuBaker.cpp uploads them).
// bake/src/gpu/GpuBaker.cpp describes the passes.
//
// Coordinates on the GPU are grid-relative and in voxels: (p - grid origin) / voxelSize, so grid
// point (i, j, k) sits exactly at (i, j, k) and float keeps ~1e-7 relative precision of numbers
// no larger than the grid, rather than of world coordinates far from the origin.
//
// The BVH and the triangles live in buffer textures (texelFetch): on llvmpipe a texel fetch is
// one vectorized load where an SSBO read is one scalar load per component and lane, and on GPUs
// it goes through the texture cache. Node texels are integer (RGBA32UI) so that no texture unit
// flushes a link word that happens to look like a denormal float.
//
//   distance nodes (RGBA32UI, floats as bits), 2 texels per node n:
//       [2n] boxMin.xyz, 0                  [2n + 1] boxMax.xyz, link
//   winding nodes (RGBA32UI, floats as bits), 2 texels per node n:
//       [2n] center.xyz, radius             [2n + 1] dipole.xyz, link
//   triangles (RGBA32F), 3 texels per triangle: a.xyz, b.xyz, c.xyz (w unused)
//
// Nodes are in depth-first preorder, so the shaders walk the tree without a stack: an internal
// node's first child is the next node, and the walk goes on after a subtree at its `skip` node.
// link = (index << kBvhLinkShift) | count: count 0 marks an internal node whose index is `skip`;
// count 1..kBvhLeafSize marks a leaf owning triangles [index, index + count), whose skip is n + 1.
#ifndef SLUICE_SHARED_SDF_BAKE_H
#define SLUICE_SHARED_SDF_BAKE_H

#include "shared/GlslBridge.h"

SLUICE_SHARED_BEGIN

/// Invocations per work group of every bake pass (1D; the shaders map them to 4 x 4 x 4 in
/// Morton order, so every 8 consecutive invocations, a SIMD register of lanes on llvmpipe, are a
/// 2 x 2 x 2 block).
SLUICE_CONST int kBakeLocalSize = 64;

/// Grid points per invocation of the fine distance pass: a block of 2 x 2 x kBakeBlockDepth, so
/// every node and triangle an invocation fetches serves 16 points (loads are what llvmpipe pays
/// for most). Blocks are aligned, so a block lies in one coarse cell.
SLUICE_CONST int kBakeBlockDepth = 4;
/// Grid points per work group of the fine distance pass: 4 x 4 x 4 blocks.
SLUICE_CONST int kBakeGroupEdge = 8;   ///< along x and y
SLUICE_CONST int kBakeGroupDepth = 16; ///< along z

/// Spacing of the coarse points [grid points]: coarse point (a, b, c) is grid point
/// min(4 (a, b, c), dims - 1). The coarse pass finds their nearest triangle (the fine pass starts
/// from those) and their sign (which covers every grid point inside their empty ball).
SLUICE_CONST int kBakeCoarseSpacing = 4;

/// Sparse bakes (program variant SDF_SPARSE) compute a list of bricks instead of the whole grid:
/// kBakeBrickSize^3 grid points each (one NanoVDB leaf), 32 blocks, with their own coarse points
/// at offsets 0, 4 and 8 along each axis (kBakeBrickCoarse^3 of them, clamped to the grid).
SLUICE_CONST int kBakeBrickSize = 8;
SLUICE_CONST int kBakeBrickCoarse = 3;

/// Texture units (buffer textures).
SLUICE_CONST int kBakeDistanceNodesUnit = 0; ///< 2 texels per node: box and link
SLUICE_CONST int kBakeTrianglesUnit = 1;     ///< 3 texels per triangle, in leaf order
SLUICE_CONST int kBakeWindingNodesUnit = 2;  ///< 2 texels per node: centroid, dipole and link

/// SSBO bindings.
SLUICE_CONST int kBakeDistanceBinding = 0; ///< float phi[] per grid point [voxels], x fastest
SLUICE_CONST int kBakeCoarseBinding = 1;   ///< CoarsePoint coarse[] per coarse point, x fastest
SLUICE_CONST int kBakePendingBinding = 2;  ///< PendingHeader, then blocks still without a sign
SLUICE_CONST int kBakeVerifyBinding = 3;   ///< PendingHeader, then points for the exact sum
/// uvec4 bricks[] (SDF_SPARSE: lower corners [grid points]) or vec4 queryPoints[] (SDF_POINTS:
/// positions [voxels], one coarse entry each).
SLUICE_CONST int kBakeBrickBinding = 4;
/// uint coarseRep[] (SDF_SPARSE): for each brick coarse entry, the first entry at the same grid
/// point (neighbouring bricks share coarse points; only that one is signed and read); then the
/// list of those first entries, which the coarse sign pass walks.
SLUICE_CONST int kBakeCoarseRepBinding = 5;

/// Most triangles in a BVH leaf, and the bits of a link that hold the count.
SLUICE_CONST int kBvhLeafSize = 4;
SLUICE_CONST int kBvhLinkShift = 3;

/// One coarse point, std430 (8 bytes).
struct CoarsePoint {
    float distance; ///< signed distance [voxels]: negative inside, 0 on the surface
    uint triangle;  ///< index of its nearest triangle (leaf order)
};

/// Header of a work list, std430. In the pending list (blocks of the fine pass with points the
/// sign pass still has to decide) a runtime-sized array of uvec2 follows it: (block index, x
/// fastest over the grid of blocks; mask of the block's pending points, bit k for point k). In
/// the verify list (points whose fast winding number is too near the decision) uint grid point
/// indices follow it.
struct PendingHeader {
    uint count;  ///< blocks written (atomicAdd)
    uint points; ///< pending points in them
    uint pad1;
    uint pad2;
};

SLUICE_SHARED_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(sluice::shared::CoarsePoint) == 8, "std430 size of CoarsePoint");
static_assert(offsetof(sluice::shared::CoarsePoint, triangle) == 4, "std430 offset of triangle");
static_assert(offsetof(sluice::shared::PendingHeader, points) == 4, "std430 offset of points");
static_assert(offsetof(sluice::shared::PendingHeader, pad1) == 8, "std430 offset of pad1");
static_assert(offsetof(sluice::shared::PendingHeader, pad2) == 12, "std430 offset of pad2");
static_assert(sizeof(sluice::shared::PendingHeader) == 16, "std430 size of PendingHeader");
static_assert(sluice::shared::kBakeGroupEdge == 4 * 2 &&
                  sluice::shared::kBakeGroupDepth == 4 * sluice::shared::kBakeBlockDepth,
              "a work group is 4 x 4 x 4 blocks");
static_assert(sluice::shared::kBakeCoarseSpacing % sluice::shared::kBakeBlockDepth == 0 &&
                  sluice::shared::kBakeCoarseSpacing % 2 == 0,
              "aligned blocks never straddle two coarse cells");
static_assert(sluice::shared::kBakeBrickSize == 2 * sluice::shared::kBakeCoarseSpacing &&
                  sluice::shared::kBakeBrickCoarse ==
                      sluice::shared::kBakeBrickSize / sluice::shared::kBakeCoarseSpacing + 1,
              "a brick is 2 x 2 x 2 coarse cells (4 x 4 x 2 blocks)");
static_assert(sluice::shared::kBvhLeafSize < (1 << sluice::shared::kBvhLinkShift),
              "a leaf's count fits the link's count bits");
#endif

#endif // SLUICE_SHARED_SDF_BAKE_H
