// Choosing the sample grid for a bake from the mesh box and the user's resolution or voxel size.
//
// The grid, exactly:
//   voxelSize = options.voxelSize if > 0, else longest side of `bounds` / resolution
//   origin    = bounds.lo - padding * voxelSize                        (per axis)
//   dims      = ceil(side / voxelSize + 2 * padding - 1e-9) + 1        (per axis, at least 2)
// so the last grid point origin + (dims - 1) * voxelSize lies at or beyond hi + padding *
// voxelSize, and a side of exactly N voxels (the longest side with --resolution N) gives
// N + 2 * padding + 1 points, not one more because of rounding (hence the 1e-9 slack, a
// billionth of a voxel). Example: resolution 32, padding 3 -> 39 points along the longest side.
#include "sluice/bake/Grid.h"

#include <cmath>
#include <string>

namespace sluice::bake {

namespace {
constexpr std::uint32_t kMaxResolution = 4096;
constexpr double kRoundingSlack = 1e-9; // [voxels]
} // namespace

Result<GridSpec> gridFor(const Box& bounds, const GridOptions& options) {
    if (bounds.empty())
        return fail(ErrorCode::InvalidArgument, "cannot place a grid: the mesh box is empty");
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(bounds.lo[a]) || !std::isfinite(bounds.hi[a]))
            return fail(ErrorCode::InvalidArgument,
                        "cannot place a grid: the mesh box is not finite");
    if (!std::isfinite(options.padding) || options.padding < 0.0)
        return fail(ErrorCode::InvalidArgument,
                    "padding must be a finite number of voxels >= 0, got " +
                        std::to_string(options.padding));
    if (!std::isfinite(options.voxelSize) || options.voxelSize < 0.0)
        return fail(ErrorCode::InvalidArgument,
                    "voxel size must be finite and > 0, got " + std::to_string(options.voxelSize));

    const glm::dvec3 side = bounds.hi - bounds.lo;
    const double longest = std::max(side.x, std::max(side.y, side.z));
    double voxelSize = options.voxelSize;
    if (voxelSize == 0.0) {
        if (options.resolution == 0 || options.resolution > kMaxResolution)
            return fail(ErrorCode::InvalidArgument,
                        "resolution must be between 1 and " + std::to_string(kMaxResolution) +
                            " voxels, got " + std::to_string(options.resolution));
        if (!(longest > 0.0))
            return fail(ErrorCode::InvalidArgument,
                        "the mesh has zero extent; give --voxel-size instead of --resolution");
        voxelSize = longest / options.resolution;
    }
    if (!(voxelSize > 0.0) || !std::isfinite(voxelSize))
        return fail(ErrorCode::InvalidArgument, "voxel size underflows for this mesh box");

    GridSpec grid;
    grid.voxelSize = voxelSize;
    grid.origin = bounds.lo - options.padding * voxelSize;
    for (int a = 0; a < 3; ++a) {
        const double cells =
            std::ceil(side[a] / voxelSize + 2.0 * options.padding - kRoundingSlack);
        // Check in double before converting, so huge voxel counts cannot wrap around.
        if (!(cells + 1.0 <= double(options.maxPoints)) || cells + 1.0 > 2147483647.0)
            return fail(ErrorCode::SizeOverflow,
                        "grid would have " + std::to_string(cells + 1.0) +
                            " points along one "
                            "axis; use a coarser resolution or a larger voxel size");
        grid.dims[a] = std::max<std::uint32_t>(2, std::uint32_t(std::max(cells, 0.0)) + 1);
    }
    // Each factor is below 2^31, so the first product cannot overflow 64 bits; check it before
    // multiplying the third.
    const std::uint64_t xy = std::uint64_t(grid.dims.x) * grid.dims.y;
    if (xy > options.maxPoints || xy * grid.dims.z > options.maxPoints)
        return fail(ErrorCode::SizeOverflow,
                    "grid of " + std::to_string(grid.dims.x) + " x " + std::to_string(grid.dims.y) +
                        " x " + std::to_string(grid.dims.z) + " points exceeds the limit of " +
                        std::to_string(options.maxPoints) +
                        "; use a coarser resolution or a larger voxel size");
    return grid;
}

} // namespace sluice::bake
