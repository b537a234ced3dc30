// Validating a sparse (NanoVDB) asset against the CGAL reference: the band, then the tiles.
//
// Two strata, both seeded and reproducible:
//   band  - active voxels (the stored exact distances), a uniform sample of them: their error
//           against the reference gives max, mean and RMS, and their central differences (where
//           all six neighbours are active too) the Eikonal figures.
//   tiles - grid points of the domain that are not active (tile, background, or clamped values
//           in band bricks), uniform over the domain: only their sign is compared, since their
//           magnitude is the band's width by construction. Deep inside counts here.
// Sign mismatches ignore points within surfaceBand voxels of the surface, as the dense check.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <nanovdb/NanoVDB.h>

#include "validate/PointComparison.h"
#include "validate/SparseValidate.h"

namespace sluice::bake::detail {

namespace {

using Tree = nanovdb::NanoTree<float>;

struct Sample {
    glm::ivec3 ijk;
    float phi;
};

/// Up to `want` active voxels, uniformly, from every leaf node of the tree.
std::vector<Sample> sampleBand(const Tree& tree, std::uint64_t want, std::uint64_t seed) {
    const std::uint64_t active = tree.activeVoxelCount();
    std::vector<Sample> out;
    if (active == 0 || want == 0)
        return out;
    const double keep = std::min(1.0, double(want) / double(active));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const auto* leaf = tree.getFirstNode<0>();
    for (std::uint32_t n = 0; n < tree.nodeCount(0); ++n, ++leaf) {
        for (auto it = leaf->beginValueOn(); it; ++it) {
            if (keep < 1.0 && u(rng) >= keep)
                continue;
            const nanovdb::Coord c = it.getCoord();
            out.push_back({{c[0], c[1], c[2]}, *it});
        }
    }
    return out;
}

/// `want` grid points of the domain that are not active voxels, uniformly (rejection).
std::vector<Sample> sampleTiles(const Tree& tree, const glm::uvec3& dims, std::uint64_t want,
                                std::uint64_t seed) {
    std::vector<Sample> out;
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<std::int32_t> ui(0, std::int32_t(dims.x) - 1),
        uj(0, std::int32_t(dims.y) - 1), uk(0, std::int32_t(dims.z) - 1);
    for (std::uint64_t tries = 0; out.size() < want && tries < 20 * want; ++tries) {
        const nanovdb::Coord c(ui(rng), uj(rng), uk(rng));
        if (tree.isActive(c))
            continue;
        out.push_back({{c[0], c[1], c[2]}, tree.getValue(c)});
    }
    return out;
}

/// |grad phi| by central differences at band samples whose six neighbours are active.
void eikonal(const Tree& tree, const std::vector<Sample>& band, double h,
             format::ValidationFigures& figures) {
    std::vector<float> norms;
    for (const Sample& s : band) {
        double g2 = 0.0;
        bool ok = true;
        for (int a = 0; a < 3 && ok; ++a) {
            nanovdb::Coord lo(s.ijk.x, s.ijk.y, s.ijk.z), hi = lo;
            lo[a] -= 1;
            hi[a] += 1;
            ok = tree.isActive(lo) && tree.isActive(hi);
            const double d = (double(tree.getValue(hi)) - tree.getValue(lo)) / (2.0 * h);
            g2 += d * d;
        }
        if (ok)
            norms.push_back(float(std::sqrt(g2)));
    }
    if (norms.empty())
        return;
    const std::size_t n = norms.size();
    figures.eikonalOutsideShare =
        double(std::count_if(norms.begin(), norms.end(),
                             [](float g) { return !(g >= 0.5f && g <= 1.5f); })) /
        double(n);
    std::nth_element(norms.begin(), norms.begin() + std::ptrdiff_t(n / 2), norms.end());
    figures.eikonalMedian = norms[n / 2];
    const std::size_t p99 = std::size_t(std::ceil(0.99 * double(n))) - 1;
    std::nth_element(norms.begin(), norms.begin() + std::ptrdiff_t(p99), norms.end());
    figures.eikonalP99 = norms[p99];
}

} // namespace

Result<ValidationReport> validateSparse(const format::ColliderAsset& asset,
                                        const CgalReference& reference,
                                        const ValidateOptions& options, Progress* progress) {
    const auto& tree = reinterpret_cast<const nanovdb::NanoGrid<float>*>(asset.grid.data())->tree();
    const double h = asset.meta.voxelSize;
    const double share = std::clamp(options.nearSurfaceShare, 0.0, 1.0);
    const auto wantBand = std::uint64_t(std::llround(share * double(options.samplePoints)));
    const std::vector<Sample> band = sampleBand(tree, wantBand, options.seed);
    const std::vector<Sample> tiles = sampleTiles(
        tree, asset.meta.dims, options.samplePoints - wantBand, options.seed ^ 0x5DEECE66Dull);

    ValidationReport report;
    report.sampled = true;
    report.referenceSign = reference.signMethod();
    format::ValidationFigures& figures = report.figures;
    const double surface = options.surfaceBand * h;
    std::vector<glm::dvec3> points;
    PointComparison c;
    for (const std::vector<Sample>* stratum : {&band, &tiles}) {
        points.clear();
        for (const Sample& s : *stratum)
            points.push_back(asset.pointPosition(std::uint32_t(s.ijk.x), std::uint32_t(s.ijk.y),
                                                 std::uint32_t(s.ijk.z)));
        const std::vector<double> exact = reference.signedDistances(points, progress);
        for (std::size_t n = 0; n < exact.size(); ++n) {
            const float phi = (*stratum)[n].phi;
            if (stratum == &band)
                c.addError(phi, exact[n], h, figures.maxError);
            c.addSign(phi, exact[n], surface);
        }
        figures.pointsChecked += exact.size();
    }
    if (!band.empty()) {
        figures.meanError = c.sum / double(band.size());
        figures.rmsError = std::sqrt(c.sumSquare / double(band.size()));
    }
    figures.signMismatches = c.mismatches;
    report.signComparedPoints = c.compared;
    report.signMismatchPercent =
        c.compared ? 100.0 * double(c.mismatches) / double(c.compared) : 0.0;
    report.bandPoints = band.size();
    report.tilePoints = tiles.size();
    eikonal(tree, band, h, figures);
    figures.known = true;
    return report;
}

} // namespace sluice::bake::detail
