// Private: the brick and block geometry both sparse backends (CGAL and GPU) share.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/bake/Grid.h"
#include "sluice/bake/sparse/SparseBaker.h"

namespace sluice::bake {

/// [grid points] in one brick of kBrickSize^3.
inline constexpr std::uint32_t kBrickVoxels = kBrickSize * kBrickSize * kBrickSize;

/// [index] Voxel `v` of a brick (0 .. kBrickVoxels - 1, x fastest) from the brick's lower corner.
inline glm::ivec3 brickVoxel(std::uint32_t v) {
    return glm::ivec3(v % kBrickSize, (v / kBrickSize) % kBrickSize, v / (kBrickSize * kBrickSize));
}

/// Whether index `p` (no coordinate negative) lies inside the domain [0, dims).
inline bool insideDomain(const glm::ivec3& p, const glm::uvec3& dims) {
    return p.x < std::int32_t(dims.x) && p.y < std::int32_t(dims.y) && p.z < std::int32_t(dims.z);
}

/// [world units] The centre of each of the plan's uniform blocks, where one sample signs the
/// whole block.
std::vector<glm::dvec3> blockCentres(const GridSpec& grid, const SparsePlan& plan);

/// Records what planSparse found, and the `seconds` it took, in `stats`.
void recordPlan(const SparsePlan& plan, double seconds, SparseBakeStats& stats);

} // namespace sluice::bake
