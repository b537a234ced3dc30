// Test helpers for sparse collider assets: a NanoVDB sphere level set, and edits of its bytes.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/Primitives.h>

#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::test {

/// A sparse asset: NanoVDB's sphere level set of `radius` [world units] around `centre`, with a
/// band of `band` voxels, interior tiles negative. dims cover the sphere and band plus 2 voxels.
inline format::ColliderAsset makeSparseSphere(double radius = 0.5, double voxelSize = 0.05,
                                              double band = 3.0,
                                              glm::dvec3 centre = {0.1, -0.2, 0.3}) {
    const double margin = radius + (band + 2.0) * voxelSize;
    const glm::dvec3 origin = centre - glm::dvec3(margin);
    auto handle = nanovdb::createLevelSetSphere<float>(
        float(radius), nanovdb::Vec3f(float(centre.x), float(centre.y), float(centre.z)), voxelSize,
        band, nanovdb::Vec3d(origin.x, origin.y, origin.z), "sphere");
    format::ColliderAsset a;
    format::ColliderMeta& m = a.meta;
    m.layout = format::Layout::Sparse;
    m.bandWidth = band;
    m.voxelSize = voxelSize;
    m.origin = origin;
    const auto n = std::uint32_t(std::ceil(2.0 * margin / voxelSize)) + 1;
    m.dims = {n, n, n};
    m.sourceFile = "sphere.obj";
    m.sourceHash = "0123456789abcdef";
    m.bake = {"cgal", 20, 5.0, "auto", format::SignMethod::Parity, 1.0};
    m.toolVersion = "sluice-bake test";
    m.mesh = {960, 482, 0, 0, 0, true, false};
    const auto* bytes = reinterpret_cast<const std::byte*>(handle.data());
    a.grid.assign(bytes, bytes + handle.size());
    return a;
}

/// The grid of a sparse asset, for reading its structure in tests (the asset must be valid).
inline const nanovdb::NanoGrid<float>& nanoGrid(const format::ColliderAsset& a) {
    return *reinterpret_cast<const nanovdb::NanoGrid<float>*>(a.grid.data());
}

/// Byte offset of `p` (a node or field inside the grid) from the grid's start.
inline std::size_t gridOffset(const format::ColliderAsset& a, const void* p) {
    return std::size_t(static_cast<const std::byte*>(p) - a.grid.data());
}

/// Writes `value` at byte `offset` of the grid.
template <class T> void pokeGrid(format::ColliderAsset& a, std::size_t offset, T value) {
    std::memcpy(a.grid.data() + offset, &value, sizeof(T));
}

} // namespace sluice::test
