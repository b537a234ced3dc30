// Whether each sparse collider's band of exact distances reaches as far as the solver reads.
#pragma once

#include <vector>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"
#include "sluice/format/scene/Scene.h"

namespace sluice::rt {

/// Band width [voxels] a sparse collider needs so that every distance the solver reads is
/// exact: the collision pass reads phi up to the particle radius, a dynamic body's boundary up
/// to h + the surface offset (docs/bodies.md); a trilinear cell reaches sqrt(3) voxels further.
/// `reach` [m] is that distance, `voxel` [m] the collider's voxel in the world (with its scale).
double requiredBandVoxels(double reach, double voxel);

/// InvalidArgument naming the scene, the collider's JSON path, the asset and the `--band` to
/// re-bake with, for the first sparse collider whose band is narrower than requiredBandVoxels;
/// dense colliders always pass.
Result<void> checkColliderBands(const format::Scene& scene,
                                const std::vector<format::ColliderAsset>& assets);

} // namespace sluice::rt
