// CPU reference of the static colliders' volume maps (docs/pbf.md, "Volume maps"): the same
// rule as pbf_volume_map.comp, in double, written from the docs.
#include "ReferencePbf.h"

#include "sluice/format/asset/GridSamples.h"
#include "sluice/format/asset/VolumeMapQuadrature.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace sluice::ref {

namespace {
constexpr int kSteps = 5;                          // quadrature points per support radius, each way
constexpr std::uint64_t kMaxPoints = 1ull << 24;   // a larger grid keeps the flat closed form

// At local point q (phi, unit normal n): the poly6-weighted share of the support of radius
// `support` the solid fills, less that of the flat boundary at phi along n, both by the same
// quadrature (a cell's solid fraction from phi at its centre, clamped linear across the cell).
// Whether q lies in the grid box, where the field holds the geometry; past it the map takes the
// solid as flat.
bool inGridBox(const format::ColliderAsset& a, glm::dvec3 q) {
    // A grid point on the box's face must count as in it, whatever the rounding of q.
    const double e = 1e-9 * a.meta.voxelSize;
    const glm::dvec3 hi = a.meta.origin + glm::dvec3(a.meta.dims - glm::uvec3(1)) * a.meta.voxelSize;
    return glm::all(glm::greaterThanEqual(q, a.meta.origin - e)) &&
           glm::all(glm::lessThanEqual(q, hi + e));
}

// The quadrature with cells d wide (quadratureCell).
double correctionAt(const format::ColliderAsset& asset, const format::SdfSampler& sampler,
                    glm::dvec3 q, double phi, glm::dvec3 n, double support, double d) {
    const int steps = int(float(support) / float(d)); // as the shader divides, in float
    return format::volumeMapQuadrature(support, d, steps, phi, n,
                                       [&](glm::dvec3 o) -> std::optional<double> {
                                           if (!inGridBox(asset, q + o))
                                               return std::nullopt;
                                           return double(sampler.value(q + o));
                                       });
}

// The quadrature's cell: a whole number of grid cells when the grid has at least kSteps cells
// per support radius (the grid's values), else support / kSteps (the field read trilinearly).
double quadratureCell(double support, double voxel) {
    const int stride = int(std::floor(support / (kSteps * voxel) + 1e-9));
    return stride > 0 ? stride * voxel : support / kSteps;
}

// Whether the field around q is the plane of phi and n: its samples on a lattice of h / 2 over
// the support within a hundredth of a quadrature cell of the plane's (the map is 0 there).
// A probe where the sample and the plane are both at least `far` from the surface on one side
// agrees (neither fills anything near it): 0.6 support, or less for a sparse asset, whose
// samples within a cell diagonal of its band's edge (bandWidth voxels) are clipped.
bool flatAround(const format::ColliderAsset& asset, const format::SdfSampler& sampler,
                glm::dvec3 q, double phi, glm::dvec3 n, double support) {
    const double step = 0.5 * support, tolerance = 0.01 * support / kSteps;
    const double voxel = asset.meta.voxelSize;
    const float clip = asset.sparse() ? float((asset.meta.bandWidth - std::sqrt(3.0)) * voxel)
                                      : std::numeric_limits<float>::infinity();
    const double far = std::min(float(0.6 * support), clip);
    for (int k = -2; k <= 2; ++k)
        for (int j = -2; j <= 2; ++j)
            for (int i = -2; i <= 2; ++i) {
                const glm::dvec3 o = glm::dvec3(i, j, k) * step;
                if (!(glm::dot(o, o) < support * support) || !inGridBox(asset, q + o))
                    continue;
                const double here = sampler.value(q + o), plane = phi + glm::dot(n, o);
                const bool beyondBand =
                    std::min(here, plane) >= far || std::max(here, plane) <= -far;
                if (!(std::abs(here - plane) <= tolerance) && !beyondBand)
                    return false;
            }
    return true;
}

// Calls visit(x, y, z) for each grid point the map holds: every grid point of a dense asset,
// every leaf voxel in the grid box of a sparse one (the GPU stores those per leaf; the
// reference keeps one array over the grid, 0 at the points in no leaf).
template <class Visit> void forEachMapPoint(const format::ColliderAsset& asset, Visit&& visit) {
    format::forEachStoredSample(asset, [&](glm::uvec3 p, float) { visit(p.x, p.y, p.z); });
}
} // namespace

std::vector<float> ReferencePbf::buildVolumeMap(const format::ColliderAsset& asset,
                                                const format::SdfSampler& sampler,
                                                double support) {
    const std::uint64_t points =
        asset.sparse() ? 512ull * format::sparseLeafCount(asset) : asset.pointCount();
    if (points > kMaxPoints)
        return {};
    const glm::uvec3 dims = asset.meta.dims;
    const double d = quadratureCell(support, asset.meta.voxelSize);
    std::vector<float> map(asset.pointCount(), 0.0f);
    forEachMapPoint(asset, [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
        const glm::dvec3 q = asset.meta.origin + glm::dvec3(x, y, z) * asset.meta.voxelSize;
        const double phi = sampler.value(q);
        // The gradient from the cell above the point (below it on the last plane), as the
        // shader takes it, whatever the rounding of q: at the cell's corner, the differences
        // along its three edges from the point.
        glm::dvec3 g(0.0);
        for (int a = 0; a < 3; ++a) {
            const double into = glm::uvec3(x, y, z)[a] + 1 >= dims[a] ? -1.0 : 1.0;
            glm::dvec3 step(0.0);
            step[a] = into * asset.meta.voxelSize;
            g[a] = (double(sampler.value(q + step)) - phi) * into / asset.meta.voxelSize;
        }
        // Particles stay outside: deeper than two cells into the solid keeps 0.
        if (!(phi > -2.0 * asset.meta.voxelSize && phi < support))
            return;
        const double len = glm::length(g);
        // On a ridge of the field the plane may face any way (same quadrature error).
        const glm::dvec3 n = len > 0.0 ? g / len : glm::dvec3(0.0, 1.0, 0.0);
        if (flatAround(asset, sampler, q, phi, n, support))
            return;
        map[x + dims.x * (y + std::size_t(dims.y) * z)] =
            float(correctionAt(asset, sampler, q, phi, n, support, d));
    });
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
