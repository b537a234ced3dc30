// A bounding volume hierarchy over a triangle soup, built on the CPU for the GPU bake shaders.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "shared/SdfBake.h"

namespace sluice::bake {

/// One triangle given to the builder, corners in grid-relative voxel coordinates [voxels].
struct BvhInputTriangle {
    glm::dvec3 a, b, c;
};

/// The tree as the texel arrays of shaders/shared/SdfBake.h: nodes in depth-first preorder
/// (node 0 is the root) with links, floats stored as their bits in RGBA32UI texels (so no
/// texture unit can flush a link that looks like a denormal float); triangles in leaf order as
/// RGBA32F texels.
struct Bvh {
    std::vector<glm::uvec4> distanceNodes; ///< 2 texels per node: box min, box max + link
    std::vector<glm::uvec4> windingNodes;  ///< 2 texels per node: centroid + radius, dipole + link
    std::vector<glm::vec4> triangles;      ///< 3 texels per triangle: corners a, b, c [voxels]
    std::uint32_t nodeCount = 0;
    std::uint32_t triangleCount = 0;
    std::uint32_t depth = 0; ///< levels below the root (0 for a single leaf)
};

/// Most triangles buildBvh accepts: node and triangle indices share a link word with the leaf
/// count (shared::kBvhLinkShift bits), and there are up to twice as many nodes as triangles.
inline constexpr std::uint64_t kBvhMaxTriangles = std::uint64_t(1) << (31 - shared::kBvhLinkShift);

/// Builds the hierarchy by binned surface-area-heuristic splits of the centroid box (median
/// splits deep down, so the depth stays below 48 + log2 n), down to leaves of at most
/// shared::kBvhLeafSize triangles (fewer than 2 n nodes for n triangles), in parallel (TBB).
/// Deterministic: the splits are stable partitions of the input order, so the same input gives
/// the same tree on every run and platform. Every node carries the data of the fast winding number
/// (Barill et al. 2018): area-weighted centroid, the radius of the ball around it holding the
/// node's corners, and the dipole term (sum of area-weighted normals), computed from the float
/// corners the GPU sees. Precondition: 1 <= input.size() < kBvhMaxTriangles.
Bvh buildBvh(std::span<const BvhInputTriangle> input);

} // namespace sluice::bake
