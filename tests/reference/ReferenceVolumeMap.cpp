// CPU reference of the static colliders' volume maps (docs/pbf.md, "Volume maps"): the same
// rule as pbf_volume_map.comp, in double, written from the docs.
#include "ReferencePbf.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace sluice::ref {

namespace {
constexpr int kSteps = 6;                          // quadrature points per support radius, each way
constexpr std::uint64_t kMaxPoints = 1ull << 24;   // a larger grid keeps the flat closed form

// At local point q (phi, unit normal n): the poly6-weighted share of the support of radius
// `support` the solid fills, less that of the flat boundary at phi along n, both by the same
// quadrature (a cell's solid fraction from phi at its centre, clamped linear across the cell).
double correctionAt(const format::SdfSampler& sampler, glm::dvec3 q, double phi, glm::dvec3 n,
                    double support) {
    const double d = support / kSteps;
    double weights = 0.0, solid = 0.0, plane = 0.0;
    for (int k = -kSteps; k <= kSteps; ++k)
        for (int j = -kSteps; j <= kSteps; ++j)
            for (int i = -kSteps; i <= kSteps; ++i) {
                const glm::dvec3 o = glm::dvec3(i, j, k) * d;
                const double a = 1.0 - glm::dot(o, o) / (support * support);
                if (!(a > 0.0))
                    continue;
                const double w = a * a * a;
                weights += w;
                solid += w * std::clamp(0.5 - sampler.value(q + o) / d, 0.0, 1.0);
                plane += w * std::clamp(0.5 - (phi + glm::dot(n, o)) / d, 0.0, 1.0);
            }
    return (solid - plane) / weights;
}
} // namespace

std::vector<float> ReferencePbf::buildVolumeMap(const format::ColliderAsset& asset,
                                                const format::SdfSampler& sampler,
                                                double support) {
    if (asset.pointCount() > kMaxPoints)
        return {};
    const glm::uvec3 dims = asset.meta.dims;
    std::vector<float> map(asset.pointCount(), 0.0f);
    for (std::uint32_t z = 0; z < dims.z; ++z)
        for (std::uint32_t y = 0; y < dims.y; ++y)
            for (std::uint32_t x = 0; x < dims.x; ++x) {
                const glm::dvec3 q = asset.meta.origin + glm::dvec3(x, y, z) * asset.meta.voxelSize;
                const double phi = sampler.value(q);
                if (!(std::abs(phi) < support))
                    continue;
                const glm::dvec3 g = sampler.gradient(q);
                const double len = glm::length(g);
                // On a ridge of the field the plane may face any way (same quadrature error).
                const glm::dvec3 n = len > 0.0 ? g / len : glm::dvec3(0.0, 1.0, 0.0);
                map[x + dims.x * (y + std::size_t(dims.y) * z)] =
                    float(correctionAt(sampler, q, phi, n, support));
            }
    return map;
}

// Trilinear in the grid box, 0 outside it; `grad` per local unit.
double ReferencePbf::volumeCorrection(const Collider& c, glm::dvec3 q, glm::dvec3& grad) const {
    grad = glm::dvec3(0.0);
    const format::ColliderAsset& a = *c.asset;
    const glm::dvec3 lo = a.meta.origin;
    const glm::dvec3 hi = lo + glm::dvec3(a.meta.dims - glm::uvec3(1)) * a.meta.voxelSize;
    if (c.volumeMap.empty() || glm::any(glm::lessThan(q, lo)) || glm::any(glm::greaterThan(q, hi)))
        return 0.0;
    const glm::uvec3 dims = a.meta.dims;
    const glm::dvec3 g = (q - lo) / a.meta.voxelSize;
    const glm::dvec3 cell = glm::clamp(glm::floor(g), glm::dvec3(0.0), glm::dvec3(dims) - 2.0);
    const glm::dvec3 t = glm::clamp(g - cell, 0.0, 1.0);
    const glm::uvec3 b(cell);
    double v[2][2][2];
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i)
                v[k][j][i] = c.volumeMap[(b.x + i) + dims.x * ((b.y + j) + std::size_t(dims.y) * (b.z + k))];
    double value = 0.0;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) {
                const double wx = i ? t.x : 1.0 - t.x, wy = j ? t.y : 1.0 - t.y,
                             wz = k ? t.z : 1.0 - t.z;
                value += wx * wy * wz * v[k][j][i];
                grad.x += (i ? 1.0 : -1.0) * wy * wz * v[k][j][i];
                grad.y += (j ? 1.0 : -1.0) * wx * wz * v[k][j][i];
                grad.z += (k ? 1.0 : -1.0) * wx * wy * v[k][j][i];
            }
    grad /= a.meta.voxelSize;
    return value;
}

} // namespace sluice::ref
