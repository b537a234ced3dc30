// The GPU record of a collider built from its asset (sluice/gpu/colliders/ColliderRecord.h).
#include "sluice/gpu/colliders/ColliderRecord.h"

#include <algorithm>
#include <string>
#include <vector>

#include "shared/Bodies.h"

namespace sluice::gpu {

shared::GpuCollider colliderRecord(const format::ColliderAsset& asset, std::uint32_t sdfOffset) {
    shared::GpuCollider r{};
    r.worldToGrid = glm::mat4(1.0f);
    r.motion = glm::mat4(1.0f);
    r.origin = glm::vec3(asset.meta.origin);
    r.voxelSize = float(asset.meta.voxelSize);
    r.boxMax = glm::vec3(asset.meta.origin +
                         glm::dvec3(asset.meta.dims - glm::uvec3(1)) * asset.meta.voxelSize);
    r.scale = 1.0f;
    r.dims = asset.meta.dims;
    r.sdfOffset = sdfOffset;
    r.body = shared::kNoBody;
    r.forceSlot = shared::kNoBody;
    r.volumeMap = shared::kNoVolumeMap;
    r.gridKind = asset.sparse() ? shared::kColliderSparse : shared::kColliderDense;
    return r;
}

Result<Buffer> colliderRecordBuffer(std::span<const shared::GpuCollider> records) {
    if (records.size() > shared::kMaxColliders)
        return fail(ErrorCode::InvalidArgument,
                    "more than " + std::to_string(shared::kMaxColliders) + " collider records");
    auto buffer = Buffer::create(kColliderRecordBytes, "colliders");
    if (!buffer)
        return buffer;
    std::vector<shared::GpuCollider> full(shared::kMaxColliders, shared::GpuCollider{});
    std::copy(records.begin(), records.end(), full.begin());
    buffer->upload(full);
    return buffer;
}

void bindColliderRecords(const Buffer& records) {
    records.bindBase(GL_UNIFORM_BUFFER, shared::kBindCollidersUniform);
    records.bindStorage(shared::kBindColliders);
}

} // namespace sluice::gpu
