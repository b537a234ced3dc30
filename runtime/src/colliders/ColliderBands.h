// Whether each sparse collider's band of exact distances reaches as far as the solver reads.
#pragma once

#include <vector>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/format/support/Result.h"

namespace sluice::rt {

/// InvalidArgument naming the scene, the collider's JSON path, the asset and the `--band` to
/// re-bake with, for the first sparse collider whose band is narrower than
/// format::requiredBandVoxels of its format::colliderReach; dense colliders always pass.
Result<void> checkColliderBands(const format::Scene& scene,
                                const std::vector<format::ColliderAsset>& assets);

} // namespace sluice::rt
