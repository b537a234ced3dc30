// How large a collider's volume map is and how its quadrature reads the grid (docs/pbf.md,
// "Volume maps"): shared by the build (VolumeMaps.cpp) and the slow-load estimate
// (play/RunProgress.cpp).
#pragma once

#include <cmath>
#include <cstdint>

#include "shared/Pbf.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/asset/GridSamples.h"
#include "sluice/gpu/colliders/VolumeMapPass.h"

namespace sluice::rt {

using format::volumeMapPoints;
static_assert(format::kMaxVolumeMapPoints == shared::kVolumeMapMaxPoints);

using gpu::volumeMapStride;

} // namespace sluice::rt
