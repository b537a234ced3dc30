// Sparse colliders' bands against the distances the solver reads.
#include "colliders/ColliderBands.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "sluice/format/scene/SolverReach.h"
#include "sluice/format/support/NumberText.h"
#include "sluice/rt/sim/SceneSetup.h"

namespace sluice::rt {

Result<void> checkColliderBands(const format::Scene& scene,
                                const std::vector<format::ColliderAsset>& assets) {
    const PbfConstants k = deriveConstants(scene.simulation);
    for (std::size_t c = 0; c < scene.colliders.size() && c < assets.size(); ++c) {
        const format::ColliderAsset& asset = assets[c];
        if (!asset.sparse())
            continue;
        const format::SceneCollider& collider = scene.colliders[c];
        const bool dynamic = collider.dynamic.has_value();
        const double reach = format::colliderReach(scene.simulation.spacing, k.h, dynamic);
        const double voxel = asset.meta.voxelSize * double(collider.scale);
        const double needed = format::requiredBandVoxels(reach, voxel);
        if (asset.meta.bandWidth >= needed)
            continue;
        const std::string path =
            collider.resolvedPath.empty() ? collider.asset : collider.resolvedPath;
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": colliders[" + std::to_string(c) + "]: " + path +
                        " is sparse with a band of " +
                        format::significant(asset.meta.bandWidth, 3) + " voxels, but " +
                        (dynamic ? "a dynamic body" : "a collider") +
                        " here reads distances up to " + format::significant(reach, 3) +
                        " m, which needs " + format::significant(needed, 3) + " voxels of " +
                        format::significant(voxel, 3) +
                        " m; re-bake it with `sluice-bake bake --sparse --band " +
                        std::to_string(int(std::ceil(needed))) + "` or bake it dense");
    }
    return {};
}

} // namespace sluice::rt
