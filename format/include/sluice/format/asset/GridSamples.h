// The samples a collider asset stores, visited in one loop for dense and sparse assets.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::format {

/// One leaf of a sparse asset's NanoVDB tree: an 8^3 block of voxels from `origin` (index
/// coordinates), its 512 values with voxel (x, y, z) of the block at values[64x + 8y + z].
struct SparseLeaf {
    glm::ivec3 origin{0};
    const float* values = nullptr; ///< points into the asset's grid bytes
};

/// The leaves of a sparse asset (empty for a dense one). The asset must outlive the result and
/// its grid must have passed checkNanoVdbGrid, as readAsset and the bakers guarantee.
std::vector<SparseLeaf> sparseLeaves(const ColliderAsset& asset);

/// The number of leaves of a sparse asset's tree (0 for a dense one), under the same condition.
std::uint32_t sparseLeafCount(const ColliderAsset& asset);

/// Points of an asset's volume map: one per grid point of a dense grid, 512 per leaf of a sparse
/// one (its band's voxels, stored per leaf as its samples are).
inline std::uint64_t volumeMapPoints(const ColliderAsset& asset) {
    return asset.sparse() ? 512ull * sparseLeafCount(asset) : asset.pointCount();
}

/// Calls visit(glm::uvec3 ijk, float phi) for every sample the asset stores: every grid point
/// of a dense asset; every leaf voxel of a sparse one inside the grid box (the band, and the
/// leaves' other voxels). A sparse asset's tiles and background, whose |phi| is the band's, are
/// not visited: this is for work near the surface (contact points, the solid's extent).
template <class Visit> void forEachStoredSample(const ColliderAsset& asset, Visit&& visit) {
    const glm::uvec3 dims = asset.meta.dims;
    if (!asset.sparse()) {
        for (std::uint32_t k = 0; k < dims.z; ++k)
            for (std::uint32_t j = 0; j < dims.y; ++j)
                for (std::uint32_t i = 0; i < dims.x; ++i)
                    visit(glm::uvec3(i, j, k), asset.distances[asset.index(i, j, k)]);
        return;
    }
    const glm::ivec3 limit(dims);
    for (const SparseLeaf& leaf : sparseLeaves(asset))
        for (int n = 0; n < 512; ++n) {
            const glm::ivec3 p = leaf.origin + glm::ivec3(n >> 6, (n >> 3) & 7, n & 7);
            if (p.x >= 0 && p.y >= 0 && p.z >= 0 && p.x < limit.x && p.y < limit.y &&
                p.z < limit.z)
                visit(glm::uvec3(p), leaf.values[n]);
        }
}

} // namespace sluice::format
