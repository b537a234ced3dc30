// The GPU record of a collider (shared/Pbf.h, GpuCollider) built from its asset: the one rule
// the solver, the volume map bake, the parity tests and the collider benchmark use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "shared/Pbf.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/gpu/Buffer.h"

namespace sluice::gpu {

/// The record of `asset` at the identity placement (unit scale, no rotation or motion), static
/// (`body` = kNoBody) and without friction, its samples at `sdfOffset` in the SDF buffer:
/// [words] for a dense grid, [bytes] for a sparse one. The caller places it and sets friction
/// and the body.
shared::GpuCollider colliderRecord(const format::ColliderAsset& asset, std::uint32_t sdfOffset);

/// Bytes of a buffer of collider records: kMaxColliders of them, the uniform block's whole
/// length (shared/Pbf.h, kBindCollidersUniform), so every read of the block is backed.
inline constexpr std::size_t kColliderRecordBytes =
    shared::kMaxColliders * sizeof(shared::GpuCollider);

/// A buffer of kColliderRecordBytes holding `records` (at most kMaxColliders; zeros after
/// them). GpuOutOfMemory if it cannot be allocated; InvalidArgument for too many records.
Result<Buffer> colliderRecordBuffer(std::span<const shared::GpuCollider> records);

/// Binds a buffer from colliderRecordBuffer where the passes read it (the uniform block) and
/// where the body pass writes it (the storage binding kBindColliders).
void bindColliderRecords(const Buffer& records);

} // namespace sluice::gpu
