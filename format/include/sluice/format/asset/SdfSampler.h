// Trilinear lookups of distance and gradient in a collider asset, defined everywhere in space.
#pragma once

#include <glm/vec3.hpp>

#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::format {

/// Samples phi and its gradient at world positions.
///
/// Lifetime: keeps a pointer to the asset, which must outlive the sampler and keep its dims and
/// distances unchanged (binding a temporary does not compile).
///
/// Inside the grid box [origin, origin + (dims - 1) * voxelSize] value() is the trilinear
/// interpolant of the samples and gradient() is its analytic gradient, taken in the cell that
/// contains the point (on a shared face the cell on the + side, except on the last plane).
///
/// Outside the box, with c = clamp(p) the nearest point of the box:
///   value(p)    = phi(c) + |p - c|      [world units]. An upper bound on the true distance
///                 (triangle inequality), exact where p - c follows the surface normal; it is
///                 positive wherever phi is positive on the box boundary (bakes pad the box), so
///                 points outside the grid always read as outside, farther the farther they are.
///   gradient(p) = the gradient of that function: the components of grad phi(c) along the axes
///                 where p is within the box's slab, plus the unit vector (p - c) / |p - c|.
///                 It points away from the box: dot(gradient(p), p - c) = |p - c| > 0.
/// A non-finite query returns NaN (value) and a NaN vector (gradient).
///
/// A sparse asset is sampled the same way, the samples read from its NanoVDB tree at index
/// (i, j, k): exact distances in the band, and outside it the tile or background value
/// (+-bandWidth voxels, the sign of the region), so deep inside reads negative.
class SdfSampler {
public:
    /// Precondition (asserted): dims >= 2 on every axis, voxelSize > 0, and
    /// distances.size() == pointCount() (dense) or a grid that passed checkNanoVdbGrid (sparse),
    /// as readAsset and the bakers guarantee.
    explicit SdfSampler(const ColliderAsset& asset);
    SdfSampler(ColliderAsset&&) = delete;

    /// phi at `world` [world units], negative inside.
    float value(const glm::dvec3& world) const;

    /// grad phi at `world` [1/1, world units per world unit]: analytic gradient of the trilinear
    /// interpolant inside, the rule above outside.
    glm::dvec3 gradient(const glm::dvec3& world) const;

    /// True if `world` lies in the closed grid box (where value() is pure interpolation).
    bool contains(const glm::dvec3& world) const;

    /// World position of the far corner of the grid box, origin + (dims - 1) * voxelSize.
    glm::dvec3 boxMax() const { return m_boxMax; }

    /// The asset sampled.
    const ColliderAsset& asset() const { return *m_asset; }

private:
    struct Cell;
    Cell locate(const glm::dvec3& clamped) const;
    double at(std::uint32_t i, std::uint32_t j, std::uint32_t k) const;

    const ColliderAsset* m_asset;
    const void* m_tree = nullptr; ///< sparse: the grid's nanovdb::NanoTree<float>
    glm::dvec3 m_boxMin;
    glm::dvec3 m_boxMax;
};

} // namespace sluice::format
