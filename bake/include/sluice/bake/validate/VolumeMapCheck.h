// Checking a volume map baked into a collider asset (sluice-bake validate) against a brute-force
// integration of what it holds (docs/pbf.md, "Volume maps").
#pragma once

#include <cstdint>
#include <vector>

#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::bake {

/// Quadrature cells per support radius, each way, of the brute-force integration: three times
/// the bake's (shared/Pbf.h, kVolumeMapSteps = 5), so the bake's own quadrature error shows.
inline constexpr int kVolumeMapCheckSteps = 15;

/// How one map compares.
struct VolumeMapCheck {
    double support = 0.0;                 ///< [asset units]
    std::uint64_t pointsChecked = 0;      ///< integrated by brute force
    std::uint64_t zeroPoints = 0;         ///< beyond the reach of the support, checked to be 0
    std::uint64_t nonZeroBeyondReach = 0; ///< of those, how many are not
    double maxError = 0.0;        ///< max |baked - brute force| [share of the kernel's weight]
    double meanError = 0.0;       ///< mean of the same
    std::uint64_t worstPoint = 0; ///< the map point (its index) of maxError
};

/// Compares `map` of `asset` with a brute-force integration. At every map point whose phi lies
/// in (-2 voxels, support), the poly6-weighted share of the support the solid fills less the
/// share the flat boundary through the point fills (phi and normal there), on a lattice of
/// kVolumeMapCheckSteps cells per support radius, the field read trilinearly at every lattice
/// point inside the grid box, with no shortcut for flat regions; at most `maxPoints` of them (a
/// fixed stride over them beyond that). Every other map point must be 0. Precondition:
/// map.values.size() == format::volumeMapPoints(asset), as readAsset guarantees.
VolumeMapCheck checkVolumeMap(const format::ColliderAsset& asset, const format::VolumeMap& map,
                              std::uint64_t maxPoints = 4000);

/// checkVolumeMap of every map the asset holds.
std::vector<VolumeMapCheck> checkVolumeMaps(const format::ColliderAsset& asset,
                                            std::uint64_t maxPoints = 4000);

} // namespace sluice::bake
