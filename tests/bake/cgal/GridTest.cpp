// The bake grid: its resolution, voxel size and padding, and the options it refuses.
#include <cstdint>

#include <gtest/gtest.h>

#include "TestMeshes.h"
#include "sluice/bake/Grid.h"

namespace {

using namespace sluice;
using namespace sluice::bake;

// --- Grid ------------------------------------------------------------------------------------

TEST(Grid, ResolutionCountsVoxelsAlongTheLongestSide) {
    const Box box{{-1, 0, 2}, {1, 1, 2.5}}; // 2 x 1 x 0.5
    Result<GridSpec> grid = gridFor(box, {.resolution = 32, .padding = 3});
    ASSERT_TRUE(grid.ok()) << grid.error().message();
    EXPECT_DOUBLE_EQ(grid->voxelSize, 2.0 / 32);
    // 32 + 2*3 voxels -> 39 points; 16 + 6 -> 23; 8 + 6 -> 15.
    EXPECT_EQ(grid->dims, glm::uvec3(39, 23, 15));
    EXPECT_DOUBLE_EQ(grid->origin.x, -1 - 3 * grid->voxelSize);
    EXPECT_DOUBLE_EQ(grid->origin.y, 0 - 3 * grid->voxelSize);
    EXPECT_DOUBLE_EQ(grid->origin.z, 2 - 3 * grid->voxelSize);
}

TEST(Grid, VoxelSizeOverridesResolutionAndRoundsPartialVoxelsUp) {
    const Box box{{0, 0, 0}, {1.05, 0.5, 0.25}};
    Result<GridSpec> grid = gridFor(box, {.resolution = 7, .voxelSize = 0.1, .padding = 1});
    ASSERT_TRUE(grid.ok()) << grid.error().message();
    EXPECT_EQ(grid->voxelSize, 0.1);
    // x: 10.5 voxels + 2 padding -> 13 voxels, 14 points; y: 5 + 2 -> 8; z: 2.5 + 2 -> 5 -> 6.
    EXPECT_EQ(grid->dims, glm::uvec3(14, 8, 6));
}

TEST(Grid, CoversThePaddedBoxOnEverySide) {
    const Box box{{-0.37, 1.11, 5.0}, {2.93, 1.2, 7.77}};
    for (double padding : {0.0, 0.5, 3.0}) {
        for (std::uint32_t resolution : {1u, 7u, 64u, 333u}) {
            Result<GridSpec> grid = gridFor(box, {.resolution = resolution, .padding = padding});
            ASSERT_TRUE(grid.ok());
            const glm::dvec3 last = grid->origin + glm::dvec3(grid->dims - 1u) * grid->voxelSize;
            for (int a = 0; a < 3; ++a) {
                EXPECT_LE(grid->origin[a], box.lo[a] - padding * grid->voxelSize + 1e-12);
                EXPECT_GE(last[a], box.hi[a] + padding * grid->voxelSize - 1e-9 * grid->voxelSize);
                // ... and by less than one voxel too much.
                EXPECT_LT(last[a], box.hi[a] + (padding + 1) * grid->voxelSize);
                EXPECT_GE(grid->dims[a], 2u);
            }
        }
    }
}

TEST(Grid, GivesAFlatMeshTwoPointsAcrossWithoutPadding) {
    Result<GridSpec> grid = gridFor(Box{{0, 0, 0}, {1, 1, 0}}, {.resolution = 4, .padding = 0});
    ASSERT_TRUE(grid.ok());
    EXPECT_EQ(grid->dims, glm::uvec3(5, 5, 2));
}

TEST(Grid, RejectsBadOptionsAsInvalidArgument) {
    const Box box{{0, 0, 0}, {1, 1, 1}};
    const double nan = std::nan("");
    for (const GridOptions& options :
         {GridOptions{.resolution = 0}, GridOptions{.resolution = 4097},
          GridOptions{.padding = -1.0}, GridOptions{.padding = nan}, GridOptions{.voxelSize = -0.1},
          GridOptions{.voxelSize = nan},
          GridOptions{.voxelSize = std::numeric_limits<double>::infinity()}}) {
        Result<GridSpec> grid = gridFor(box, options);
        ASSERT_FALSE(grid.ok());
        EXPECT_EQ(grid.error().code, ErrorCode::InvalidArgument) << grid.error().message();
    }
    EXPECT_EQ(gridFor(Box{}, {}).error().code, ErrorCode::InvalidArgument); // empty
    EXPECT_EQ(gridFor(Box{{1, 1, 1}, {1, 1, 1}}, {}).error().code, ErrorCode::InvalidArgument);
}

TEST(Grid, RejectsMoreThanTheLargestGridAsSizeOverflow) {
    const Box box{{0, 0, 0}, {1, 1, 1}};
    EXPECT_EQ(gridFor(box, {.resolution = 4096}).error().code, ErrorCode::SizeOverflow);
    EXPECT_EQ(gridFor(box, {.voxelSize = 1e-12}).error().code, ErrorCode::SizeOverflow);
    EXPECT_TRUE(gridFor(box, {.resolution = 600}).ok()); // 607^3 = 224 M points < 268 M
}

} // namespace
