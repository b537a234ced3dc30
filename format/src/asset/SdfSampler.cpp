// Trilinear interpolation of the distance grid and its analytic gradient; rule for outside.
#include "sluice/format/asset/SdfSampler.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <nanovdb/NanoVDB.h>

#include "sluice/format/support/Assert.h"

namespace sluice::format {

struct SdfSampler::Cell {
    std::uint32_t i, j, k; ///< lower corner of the cell, each <= dims - 2
    glm::dvec3 t;          ///< position inside the cell, each in [0, 1]
};

namespace {
bool finite(const glm::dvec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
} // namespace

SdfSampler::SdfSampler(const ColliderAsset& asset) : m_asset(&asset) {
    const ColliderMeta& m = asset.meta;
    SLUICE_ASSERT(m.dims.x >= 2 && m.dims.y >= 2 && m.dims.z >= 2, "SdfSampler: dims below 2");
    SLUICE_ASSERT(m.voxelSize > 0.0, "SdfSampler: voxel size not > 0");
    if (asset.sparse()) {
        SLUICE_ASSERT(asset.grid.size() >= sizeof(nanovdb::GridData) + sizeof(nanovdb::TreeData<3>),
                      "SdfSampler: sparse asset without a grid");
        const auto* grid = reinterpret_cast<const nanovdb::NanoGrid<float>*>(asset.grid.data());
        m_tree = &grid->tree();
    } else {
        SLUICE_ASSERT(asset.distances.size() == asset.pointCount(),
                      "SdfSampler: distance count differs from dims");
    }
    m_boxMin = m.origin;
    m_boxMax = m.origin + glm::dvec3(m.dims - glm::uvec3(1)) * m.voxelSize;
}

bool SdfSampler::contains(const glm::dvec3& p) const {
    return p.x >= m_boxMin.x && p.y >= m_boxMin.y && p.z >= m_boxMin.z && p.x <= m_boxMax.x &&
           p.y <= m_boxMax.y && p.z <= m_boxMax.z;
}

double SdfSampler::at(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
    if (m_tree) // index coordinates stay below dims (at most a few thousand): int32 holds them
        return static_cast<const nanovdb::NanoTree<float>*>(m_tree)->getValue(
            nanovdb::Coord(std::int32_t(i), std::int32_t(j), std::int32_t(k)));
    return m_asset->distances[m_asset->index(i, j, k)];
}

SdfSampler::Cell SdfSampler::locate(const glm::dvec3& q) const {
    const glm::dvec3 g = (q - m_boxMin) / m_asset->meta.voxelSize; // grid coordinates
    const glm::uvec3& dims = m_asset->meta.dims;
    Cell c{};
    std::uint32_t* idx[3] = {&c.i, &c.j, &c.k};
    for (int a = 0; a < 3; ++a) {
        // The last plane belongs to the cell below it, so every cell index is <= dims - 2.
        const double lo = std::clamp(std::floor(g[a]), 0.0, double(dims[a] - 2));
        *idx[a] = std::uint32_t(lo);
        c.t[a] = std::clamp(g[a] - lo, 0.0, 1.0);
    }
    return c;
}

float SdfSampler::value(const glm::dvec3& p) const {
    if (!finite(p))
        return float(kNaN);
    const glm::dvec3 q = glm::clamp(p, m_boxMin, m_boxMax);
    const Cell c = locate(q);
    const glm::dvec3& t = c.t;
    const double c00 = glm::mix(at(c.i, c.j, c.k), at(c.i + 1, c.j, c.k), t.x);
    const double c10 = glm::mix(at(c.i, c.j + 1, c.k), at(c.i + 1, c.j + 1, c.k), t.x);
    const double c01 = glm::mix(at(c.i, c.j, c.k + 1), at(c.i + 1, c.j, c.k + 1), t.x);
    const double c11 = glm::mix(at(c.i, c.j + 1, c.k + 1), at(c.i + 1, c.j + 1, c.k + 1), t.x);
    const double inside = glm::mix(glm::mix(c00, c10, t.y), glm::mix(c01, c11, t.y), t.z);
    return float(inside + glm::length(p - q));
}

glm::dvec3 SdfSampler::gradient(const glm::dvec3& p) const {
    if (!finite(p))
        return glm::dvec3(kNaN);
    const glm::dvec3 q = glm::clamp(p, m_boxMin, m_boxMax);
    const Cell c = locate(q);
    const glm::dvec3& t = c.t;
    const std::uint32_t i = c.i, j = c.j, k = c.k;
    double v[2][2][2];
    for (std::uint32_t a = 0; a < 2; ++a)
        for (std::uint32_t b = 0; b < 2; ++b)
            for (std::uint32_t d = 0; d < 2; ++d)
                v[a][b][d] = at(i + a, j + b, k + d);

    // Partial derivatives of the trilinear interpolant: a difference along one axis, bilinearly
    // weighted over the other two, divided by the spacing.
    const double h = m_asset->meta.voxelSize;
    const double wx[2] = {1.0 - t.x, t.x}, wy[2] = {1.0 - t.y, t.y}, wz[2] = {1.0 - t.z, t.z};
    glm::dvec3 g{0.0};
    for (int m = 0; m < 2; ++m)
        for (int n = 0; n < 2; ++n) {
            g.x += wy[m] * wz[n] * (v[1][m][n] - v[0][m][n]);
            g.y += wx[m] * wz[n] * (v[m][1][n] - v[m][0][n]);
            g.z += wx[m] * wy[n] * (v[m][n][1] - v[m][n][0]);
        }
    g /= h;

    const glm::dvec3 out = p - q;
    const double dist = glm::length(out);
    if (dist == 0.0)
        return g;
    // Outside: d/dp phi(clamp(p)) loses the clamped axes; d/dp |p - c| = (p - c) / |p - c|.
    for (int a = 0; a < 3; ++a)
        if (out[a] != 0.0)
            g[a] = 0.0;
    return g + out / dist;
}

} // namespace sluice::format
