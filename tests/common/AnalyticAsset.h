// Collider assets sampled from analytic signed distance functions, for tests of everything that
// reads assets (the interop, slice pictures, the runtime) without baking a mesh.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>

#include <glm/glm.hpp>

#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::testasset {

/// Exact SDF of the axis-aligned box [lo, hi], corners and edges included (negative inside).
inline double boxSdf(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
    const glm::dvec3 q = glm::abs(p - c) - h;
    const double outside = glm::length(glm::max(q, glm::dvec3(0.0)));
    const double inside = std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
    return outside + inside;
}

/// Exact SDF of a sphere (negative inside).
inline double sphereSdf(const glm::dvec3& p, const glm::dvec3& center, double radius) {
    return glm::length(p - center) - radius;
}

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
