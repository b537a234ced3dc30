// How sparse colliders' NanoVDB grids are packed into one GPU buffer (the solver's SDF buffer,
// the renderer's sparse buffer, the volume map bake's): back to back, each at a 32-byte aligned
// offset.
#pragma once

#include <cstdint>

#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::gpu {

/// `bytes` rounded up to NanoVDB's 32-byte alignment.
inline std::uint64_t alignToGrid(std::uint64_t bytes) {
    return (bytes + 31u) & ~std::uint64_t(31u);
}

/// Bytes a sparse collider's grid takes in a packed buffer, so the next grid starts aligned.
inline std::uint64_t sparseSlotBytes(const format::ColliderAsset& asset) {
    return alignToGrid(asset.grid.size());
}

} // namespace sluice::gpu
