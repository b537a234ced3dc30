// The solver's GPU record of a collider built from its asset (sluice/rt/ColliderRecord.h).
#include "sluice/rt/sim/ColliderRecord.h"

#include "shared/Bodies.h"

namespace sluice::rt {

shared::GpuCollider colliderRecord(const format::ColliderAsset& asset, std::uint32_t sdfOffset) {
    shared::GpuCollider r{};
    r.worldToGrid = glm::mat4(1.0f);
    r.rotation = glm::mat4(1.0f);
    r.motion = glm::mat4(1.0f);
    r.origin = glm::vec3(asset.meta.origin);
    r.voxelSize = float(asset.meta.voxelSize);
    r.boxMax = glm::vec3(asset.meta.origin +
                         glm::dvec3(asset.meta.dims - glm::uvec3(1)) * asset.meta.voxelSize);
    r.scale = 1.0f;
    r.dims = asset.meta.dims;
    r.sdfOffset = sdfOffset;
    r.body = shared::kNoBody;
    r.volumeMap = shared::kNoVolumeMap;
    r.gridKind = asset.sparse() ? shared::kColliderSparse : shared::kColliderDense;
    return r;
}

} // namespace sluice::rt
