// Sparse bakes: a narrow band of exact distances in a NanoVDB grid, with signed tiles elsewhere.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/Grid.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// Most grid points a sparse bake's domain may span [grid points]: 2^40 (e.g. 10^4 per axis).
/// Only the band is stored, so this bounds coordinates, not memory.
inline constexpr std::uint64_t kMaxSparseGridPoints = std::uint64_t(1) << 40;
/// [voxels] edge of a brick, the unit of band work: one NanoVDB leaf node.
inline constexpr std::uint32_t kBrickSize = 8;

/// The settings of a sparse bake on top of BakeSettings.
struct SparseSettings {
    double band = 3.0; ///< [voxels] half-width of the band of exact values, 1..64
};

/// [voxels] The padding a sparse bake uses for a requested `padding`: at least band + 1, so the
/// band fits inside the domain. The asset records it.
double sparsePadding(double padding, double band);

/// The sparse grid for a mesh: as gridFor, with the padding raised to at least band + 1 voxels
/// (so the band fits inside the domain) and no dense point limit (kMaxSparseGridPoints instead).
Result<GridSpec> sparseGridFor(const Box& bounds, GridOptions options, double band);

/// The band [whole voxels] a sparse collider baked over `bounds` with `options` needs where a
/// scene of particle spacing `spacing` [world units] and kernel radius `kernelRadius` (0: the
/// default, format::kDefaultKernelSpacings spacings) places it at scale 1, as a static collider
/// or a dynamic body: format::requiredBandVoxels of the dynamic format::colliderReach, rounded
/// up, at least 1. InvalidArgument for a spacing that is not > 0, a kernel radius outside the
/// scene's range, or a band over 64 voxels (a finer spacing, or a coarser grid, then).
Result<double> bandForSpacing(const Box& bounds, const GridOptions& options, double spacing,
                              double kernelRadius);

/// bandForSpacing on a grid of voxels of `voxel` [world units] (an asset's, or gridFor's).
Result<double> bandForVoxel(double voxel, double spacing, double kernelRadius);

/// Which parts of the domain need exact distances: bricks of kBrickSize^3 voxels (index-space
/// lower corners, multiples of kBrickSize) that may hold a voxel within the band, and blocks of
/// power-of-two edge with no surface near them (uniform sign, one sample at their centre).
struct SparsePlan {
    std::vector<glm::ivec3> bricks;      ///< [index] lower corners of the band bricks
    std::vector<glm::ivec3> blocks;      ///< [index] lower corners of the uniform blocks
    std::vector<std::int32_t> blockEdge; ///< [voxels] edge of each uniform block
    std::uint64_t distanceQueries = 0;   ///< unsigned distance queries the culling made
};

/// Unsigned distances [world units] from the mesh to each of `points`, written to `distances`
/// (as many). A query may understate a distance (never overstate it): culling stays safe.
using DistanceQuery =
    std::function<void(std::span<const glm::dvec3> points, std::span<double> distances)>;

/// Finds the band bricks by recursive culling: a block of edge S whose centre lies farther from
/// the surface than its half-diagonal plus the band holds no band voxel and is uniform; otherwise
/// it splits in 8 down to bricks. Blocks outside the domain [0, dims) are dropped. Each level's
/// centres go to `unsignedDistance` as one batch. Work grows with the surface area, not the
/// volume.
SparsePlan planSparse(const GridSpec& grid, double band, const DistanceQuery& unsignedDistance);

/// The provenance of a sparse bake: bakeProvenance's, with the sparse layout, f32 storage, the
/// band and the padding the bake used (sparsePadding).
format::ColliderMeta sparseProvenance(const ImportedMesh& mesh, const GridSpec& grid,
                                      const BakeSettings& settings, const char* backend,
                                      format::SignMethod method, double band);

/// What a sparse bake did and what it cost.
struct SparseBakeStats {
    std::uint64_t bricks = 0;          ///< band bricks computed
    std::uint64_t uniformBlocks = 0;   ///< blocks signed by one sample
    std::uint64_t voxelsComputed = 0;  ///< exact distances computed (brick voxels in the domain)
    std::uint64_t distanceQueries = 0; ///< culling queries
    std::uint64_t activeVoxels = 0;    ///< band voxels stored
    std::uint64_t gridBytes = 0;       ///< [bytes] the NanoVDB grid
    double planSeconds = 0.0;          ///< culling
    double distanceSeconds = 0.0;      ///< exact distances and signs of brick voxels and blocks
    double buildSeconds = 0.0;         ///< OpenVDB tree and NanoVDB conversion
};

/// Builds the NanoVDB grid of a sparse bake, brick batch by brick batch so that exact values
/// never sit in memory twice: band bricks clamped to +-band voxels and active where
/// |phi| < band voxels, uniform inside blocks filled with -band voxels, background +band voxels
/// elsewhere. Class level set, named "sdf", index (i, j, k) at grid.origin + (i, j, k) *
/// voxelSize.
class SparseGridBuilder {
public:
    SparseGridBuilder(const GridSpec& grid, double band);
    ~SparseGridBuilder();
    SparseGridBuilder(const SparseGridBuilder&) = delete;
    SparseGridBuilder& operator=(const SparseGridBuilder&) = delete;

    /// Adds bricks: kBrickSize^3 signed distances per corner [world units], x fastest; entries
    /// outside the domain [0, dims) are ignored. Each brick is added once.
    void addBricks(std::span<const glm::ivec3> corners, std::span<const float> values);
    /// Marks the block of `edge` voxels at `lo` as inside the solid (no brick overlaps it).
    void fillInside(const glm::ivec3& lo, std::int32_t edge);
    /// The grid, as NanoVDB bytes; the builder is empty afterwards. Unsupported if OpenVDB or
    /// NanoVDB fail (their exceptions), SizeOverflow if the grid exceeds kMaxNanoVdbBytes.
    Result<format::GridBytes> finish();

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// The end of a sparse bake: fills the plan's uniform blocks whose centre is inside
/// (`blockPhi` < 0, one per block) as inside tiles, finishes the builder's grid and returns the
/// asset with `meta`; adds the time to stats.buildSeconds and sets activeVoxels and gridBytes.
/// Errors: those of SparseGridBuilder::finish.
Result<format::ColliderAsset> finishSparseAsset(SparseGridBuilder& builder, const SparsePlan& plan,
                                                std::span<const double> blockPhi,
                                                format::ColliderMeta meta, SparseBakeStats& stats);

} // namespace sluice::bake
