// A mesh as the baker sees it: welded positions and triangles, in world units.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace sluice::bake {

/// Axis-aligned box [world units]. Empty when lo > hi on any axis.
struct Box {
    glm::dvec3 lo{1e300};
    glm::dvec3 hi{-1e300};
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
};

/// Triangles indexing welded vertex positions (identical positions share one index).
/// Open, non-manifold and self-intersecting soups are allowed.
struct TriangleSoup {
    std::vector<glm::dvec3> positions; ///< [world units]
    std::vector<glm::uvec3> triangles; ///< indices into positions

    /// Bounding box of the positions referenced by triangles.
    Box bounds() const;
};

} // namespace sluice::bake
