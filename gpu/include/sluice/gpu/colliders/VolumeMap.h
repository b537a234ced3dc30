// A collider's volume map for the boundary model (docs/pbf.md, "Volume maps"), computed on the
// GPU by the solver's own pass, for baking it into the asset (sluice-bake bake --volume-map).
#pragma once

#include <vector>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::gpu {

/// The volume map of `asset` for kernel radius `support` [asset units: h over the placement
/// scale]: one value per map point (format::volumeMapPoints), exactly what a scene of that h
/// builds at load from the field as stored (an f16 asset's samples rounded to half first).
/// Needs a current GL 4.5 context with compute shaders. InvalidArgument for a support that is
/// not a number between a hundredth of a voxel and the grid's diagonal; SizeOverflow for a map
/// of more than format::kMaxVolumeMapPoints points; GpuOutOfMemory when the grid and the map do
/// not fit one storage block; a GL error if the pass cannot be built.
Result<std::vector<float>> computeVolumeMap(const format::ColliderAsset& asset, double support);

} // namespace sluice::gpu
