// How large a collider's volume map is and how its quadrature reads the grid (docs/pbf.md,
// "Volume maps"): shared by the build (VolumeMaps.cpp) and the slow-load estimate
// (play/RunProgress.cpp).
#pragma once

#include <cmath>
#include <cstdint>

#include "shared/Pbf.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/asset/GridSamples.h"

namespace sluice::rt {

/// Points of an asset's volume map: one per grid point of a dense grid, 512 per leaf of a sparse
/// one (its band's voxels, stored per leaf).
inline std::uint64_t volumeMapPoints(const format::ColliderAsset& asset) {
    return asset.sparse() ? 512ull * format::sparseLeafCount(asset) : asset.pointCount();
}

/// The quadrature's cell in grid cells (pbf_volume_map.comp): the most that keeps at least
/// kVolumeMapSteps cells per support radius, or 0 when even one grid cell is coarser than that
/// (then the field is read trilinearly at support / kVolumeMapSteps).
inline std::uint32_t volumeMapStride(double support, double voxelSize) {
    return std::uint32_t(std::floor(support / (shared::kVolumeMapSteps * voxelSize) + 1e-9));
}

} // namespace sluice::rt
