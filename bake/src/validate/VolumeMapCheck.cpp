// A volume map against a brute-force integration of its definition, on the CPU: a finer lattice
// than the bake's, the asset's trilinear field at every lattice point, no flat-region shortcut.
#include "sluice/bake/validate/VolumeMapCheck.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
#include <tbb/parallel_for.h>

#include "sluice/format/asset/GridSamples.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/format/asset/VolumeMapQuadrature.h"

namespace sluice::bake {
namespace {

// The grid point of map point n: grid order for a dense asset, leaf n / 512 voxel n % 512 (x
// slowest, NanoVDB's order) for a sparse one. False for a leaf voxel past the grid box.
bool mapPointAt(const format::ColliderAsset& asset, const std::vector<format::SparseLeaf>& leaves,
                std::uint64_t n, glm::ivec3& p) {
    const glm::uvec3 dims = asset.meta.dims;
    if (!asset.sparse()) {
        p = glm::ivec3(int(n % dims.x), int((n / dims.x) % dims.y),
                       int(n / (std::uint64_t(dims.x) * dims.y)));
        return true;
    }
    const std::uint32_t v = std::uint32_t(n % 512);
    p = leaves[n / 512].origin + glm::ivec3(int(v >> 6), int((v >> 3) & 7u), int(v & 7u));
    return glm::all(glm::greaterThanEqual(p, glm::ivec3(0))) &&
           glm::all(glm::lessThan(p, glm::ivec3(dims)));
}

// The share the map holds at grid point p, integrated on the fine lattice.
double bruteForceShare(const format::SdfSampler& field, glm::ivec3 p, double phi, glm::dvec3 n,
                       double support) {
    const format::ColliderMeta& m = field.asset().meta;
    const glm::dvec3 q = m.origin + glm::dvec3(p) * m.voxelSize;
    const double d = support / kVolumeMapCheckSteps;
    return format::volumeMapQuadrature(
        support, d, kVolumeMapCheckSteps, phi, n, [&](glm::dvec3 o) -> std::optional<double> {
            if (!field.contains(q + o))
                return std::nullopt; // past the grid the bake takes the field as flat: both 0
            return double(field.value(q + o));
        });
}

// phi at grid point p and the unit normal there, as the bake takes them: the trilinear cell
// above p (below it on the last plane), its gradient at p's corner of that cell, so a point on a
// kink of the field (a concave edge's diagonal) gets the same side whatever the rounding.
void phiAndNormalAt(const format::SdfSampler& field, glm::ivec3 p, float& phi, glm::dvec3& n) {
    const format::ColliderMeta& m = field.asset().meta;
    const glm::ivec3 cell = glm::min(p, glm::ivec3(m.dims) - 2);
    const glm::dvec3 t = glm::dvec3(p - cell);
    double v[8];
    for (int k = 0; k < 8; ++k) {
        const glm::ivec3 corner = cell + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2);
        v[k] = field.value(m.origin + glm::dvec3(corner) * m.voxelSize);
    }
    const auto lerp = [](double a, double b, double w) { return a + (b - a) * w; };
    glm::dvec3 g;
    g.x = lerp(lerp(v[1] - v[0], v[3] - v[2], t.y), lerp(v[5] - v[4], v[7] - v[6], t.y), t.z);
    g.y = lerp(lerp(v[2] - v[0], v[3] - v[1], t.x), lerp(v[6] - v[4], v[7] - v[5], t.x), t.z);
    g.z = lerp(lerp(v[4] - v[0], v[5] - v[1], t.x), lerp(v[6] - v[2], v[7] - v[3], t.x), t.y);
    phi = float(v[std::size_t(t.x) + 2 * std::size_t(t.y) + 4 * std::size_t(t.z)]);
    const double len = glm::length(g);
    n = len > 0.0 ? g / len : glm::dvec3(0.0, 1.0, 0.0);
}

} // namespace

VolumeMapCheck checkVolumeMap(const format::ColliderAsset& asset, const format::VolumeMap& map,
                              std::uint64_t maxPoints) {
    const format::SdfSampler field(asset);
    const std::vector<format::SparseLeaf> leaves = format::sparseLeaves(asset);
    const float voxel = float(asset.meta.voxelSize);
    const float support = float(map.support);
    VolumeMapCheck check;
    check.support = map.support;
    // The points the support reaches from outside the deep interior, compared as the bake
    // compares them (in float); every other must hold 0. Counted first, then every stride-th.
    const auto reaches = [&](std::uint64_t n, glm::ivec3& p, float& phi, glm::dvec3& normal) {
        if (!mapPointAt(asset, leaves, n, p))
            return false;
        phiAndNormalAt(field, p, phi, normal);
        return phi > -2.0f * voxel && phi < support;
    };
    std::uint64_t reached = 0;
    for (std::uint64_t n = 0; n < map.values.size(); ++n) {
        glm::ivec3 p;
        float phi;
        glm::dvec3 normal;
        if (reaches(n, p, phi, normal)) {
            ++reached;
            continue;
        }
        ++check.zeroPoints;
        check.nonZeroBeyondReach += map.values[n] != 0.0f;
    }
    const std::uint64_t stride = std::max<std::uint64_t>(
        1, (reached + maxPoints - 1) / std::max<std::uint64_t>(1, maxPoints));
    struct Checked {
        std::uint64_t n;
        glm::ivec3 p;
        float phi;
        glm::dvec3 normal;
    };
    std::vector<Checked> checked;
    for (std::uint64_t n = 0, r = 0; n < map.values.size(); ++n) {
        Checked c{n, {}, 0.0f, {}};
        if (!reaches(n, c.p, c.phi, c.normal))
            continue;
        if (r++ % stride == 0)
            checked.push_back(c);
    }
    std::vector<double> errors(checked.size());
    tbb::parallel_for(std::size_t(0), checked.size(), [&](std::size_t r) {
        const Checked& at = checked[r];
        const double exact = bruteForceShare(field, at.p, at.phi, at.normal, map.support);
        errors[r] = std::abs(double(map.values[at.n]) - exact);
    });
    check.pointsChecked = checked.size();
    double sum = 0.0;
    for (std::size_t r = 0; r < errors.size(); ++r) {
        sum += errors[r];
        if (errors[r] > check.maxError) {
            check.maxError = errors[r];
            check.worstPoint = checked[r].n;
        }
    }
    check.meanError = errors.empty() ? 0.0 : sum / double(errors.size());
    return check;
}

std::vector<VolumeMapCheck> checkVolumeMaps(const format::ColliderAsset& asset,
                                            std::uint64_t maxPoints) {
    std::vector<VolumeMapCheck> out;
    for (const format::VolumeMap& map : asset.volumeMaps)
        out.push_back(checkVolumeMap(asset, map, maxPoints));
    return out;
}

} // namespace sluice::bake
