// Collider assets sampled from analytic signed distance functions, for tests of everything that
// reads assets (the interop, slice pictures, the runtime) without baking a mesh.
#pragma once

#include <cstdint>
#include <functional>

#include <glm/glm.hpp>

#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::testasset {

/// An asset of `dims` grid points from `origin` at `voxelSize` [world units] holding `sdf` at
/// every point, with fixed provenance (source "analytic.obj", backend "analytic").
inline format::ColliderAsset assetFromSdf(glm::uvec3 dims, glm::dvec3 origin, double voxelSize,
                                          const std::function<double(const glm::dvec3&)>& sdf) {
    format::ColliderAsset asset;
    asset.meta.dims = dims;
    asset.meta.origin = origin;
    asset.meta.voxelSize = voxelSize;
    asset.meta.sourceFile = "analytic.obj";
    asset.meta.sourceHash = "0123456789abcdef";
    asset.meta.toolVersion = "sluice-bake 0.1.0";
    asset.meta.bake.backend = "analytic";
    asset.distances.resize(asset.pointCount());
    for (std::uint32_t k = 0; k < dims.z; ++k)
        for (std::uint32_t j = 0; j < dims.y; ++j)
            for (std::uint32_t i = 0; i < dims.x; ++i)
                asset.distances[asset.index(i, j, k)] = float(sdf(asset.pointPosition(i, j, k)));
    return asset;
}

} // namespace sluice::testasset
