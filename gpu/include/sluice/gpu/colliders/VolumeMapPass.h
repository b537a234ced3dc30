// The volume map pass (shaders/colliders/pbf_volume_map.comp, docs/pbf.md "Volume maps"): its
// program and one collider's map dispatched with it. Shared by the solver, which builds the maps
// a scene needs at load (runtime/src/colliders/VolumeMaps.cpp), and computeVolumeMap, which bakes
// one into an asset (VolumeMap.h).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "shared/Pbf.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"
#include "sluice/gpu/Program.h"

namespace sluice::gpu {

/// The quadrature's cell in grid cells: the most that keeps at least kVolumeMapSteps cells per
/// support radius, or 0 when even one grid cell is coarser than that (then the field is read
/// trilinearly at support / kVolumeMapSteps).
inline std::uint32_t volumeMapStride(double support, double voxelSize) {
    return std::uint32_t(std::floor(support / (shared::kVolumeMapSteps * voxelSize) + 1e-9));
}

/// The pass, compiled with the colliders' `defines` (sparse reader, SDF from storage).
Result<Program> volumeMapProgram(const std::vector<ShaderDefine>& defines);

/// Dispatches `pass` for collider `collider` of `asset` and kernel radius `support` [asset
/// units]: it writes the map where the collider's record says (GpuCollider::volumeMap, in the
/// buffer bound at kBindVolumeMapOut). Precondition: the collider records and the SDF buffer
/// are bound as the solver binds them.
void dispatchVolumeMap(const Program& pass, std::uint32_t collider,
                       const format::ColliderAsset& asset, double support);

} // namespace sluice::gpu
