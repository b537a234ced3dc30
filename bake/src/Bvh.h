// A bounding volume hierarchy over a triangle soup, built on the CPU for the GPU bake shaders.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "shared/SdfBake.h"

namespace sluice::bake {

/// One triangle given to the builder, corners in grid-relative voxel coordinates [voxels].
struct BvhInputTriangle {
    glm::dvec3 a, b, c;
};

/// The tree in the std430 layout of shaders/shared/SdfBake.h: nodes in depth-first preorder
/// with skip links (nodes[0] is the root), triangles in leaf order as floats.
struct Bvh {
    std::vector<shared::BvhNode> nodes;
    std::vector<shared::BvhTriangle> triangles;
    std::uint32_t depth = 0; ///< levels below the root (0 for a single leaf)
};

/// Builds the hierarchy by median splits on the longest axis of the centroid box, down to
/// leaves of at most shared::kBvhLeafSize triangles. Deterministic: ties are broken by input
/// index, so the same input gives the same tree on every run and platform. Every node carries
/// the data of the fast winding number (Barill et al. 2018): area-weighted centroid, the radius
/// of the ball around it holding the node's corners, and the dipole term (sum of area-weighted
/// normals), computed from the float corners the GPU sees. Precondition: at least one triangle;
/// fewer than 2^31 triangles.
Bvh buildBvh(std::span<const BvhInputTriangle> input);

} // namespace sluice::bake
