// Choosing the sample grid for a bake from the mesh box and the user's resolution or voxel size.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "sluice/bake/import/TriangleSoup.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// Largest grid a bake accepts [grid points]; beyond it, SizeOverflow.
inline constexpr std::uint64_t kMaxGridPoints = std::uint64_t(1024) * 1024 * 1024 / 4; // 1 GiB fp32

struct GridOptions {
    std::uint32_t resolution = 64; ///< [voxels] along the longest box side; used if voxelSize == 0
    double voxelSize = 0.0;        ///< [world units]; overrides resolution when > 0
    double padding = 3.0;          ///< [voxels] added on every side; finite, >= 0
    std::uint64_t maxPoints = kMaxGridPoints; ///< [grid points] limit; sparse bakes raise it
};

/// Sample points origin + (i, j, k) * voxelSize for i < dims.x etc.
struct GridSpec {
    glm::uvec3 dims{0};     ///< [grid points]
    glm::dvec3 origin{0.0}; ///< [world units]
    double voxelSize = 0.0; ///< [world units]
    std::uint64_t pointCount() const { return std::uint64_t(dims.x) * dims.y * dims.z; }
};

/// Grid covering `bounds` plus padding. Errors: InvalidArgument (empty box, non-positive or
/// non-finite values, resolution 0 or over 4096), SizeOverflow (more than options.maxPoints).
Result<GridSpec> gridFor(const Box& bounds, const GridOptions& options);

} // namespace sluice::bake
