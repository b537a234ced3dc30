// bake::validate: compares a collider asset with the exact CGAL reference, point by point.
#include "sluice/bake/validate/Validate.h"

#include "validate/PointComparison.h"
#include "validate/SparseValidate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sluice::bake {
namespace {

/// splitmix64 (Steele et al. 2014): a tiny generator whose output is fixed by the seed on every
/// platform, unlike the std:: distributions, so sampled reports are reproducible anywhere.
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : m_state(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1) with 53 random bits.
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }

private:
    std::uint64_t m_state;
};

/// A stratum of grid points compared with the reference: its size in the whole grid and the
/// linear indices of the points drawn from it.
struct Stratum {
    std::uint64_t population = 0;
    std::vector<std::uint64_t> indices;
};

/// Selection sampling (Knuth, TAOCP vol. 2, 3.4.2, Algorithm S): visits the population once and
/// keeps each item with probability (still needed) / (still left), which draws exactly `wanted`
/// items uniformly without replacement, in index order, with no extra memory.
class SelectionSampler {
public:
    SelectionSampler(std::uint64_t population, std::uint64_t wanted, std::uint64_t seed)
        : m_left(population), m_needed(std::min(wanted, population)), m_rng(seed) {}
    bool take() {
        if (m_left == 0)
            return false;
        const bool keep = m_needed > 0 && m_rng.uniform() * double(m_left) < double(m_needed);
        --m_left;
        if (keep)
            --m_needed;
        return keep;
    }

private:
    std::uint64_t m_left;
    std::uint64_t m_needed;
    SplitMix64 m_rng;
};

Result<void> checkAsset(const format::ColliderAsset& asset) {
    const format::ColliderMeta& meta = asset.meta;
    if (asset.sparse())
        return {}; // the reader or the baker checked its grid
    if (meta.dims.x < 2 || meta.dims.y < 2 || meta.dims.z < 2)
        return fail(ErrorCode::InvalidArgument, "validate: the asset grid has fewer than 2 points "
                                                "along an axis");
    if (!std::isfinite(meta.voxelSize) || meta.voxelSize <= 0.0)
        return fail(ErrorCode::InvalidArgument, "validate: the asset voxel size is not positive");
    if (asset.distances.size() != asset.pointCount())
        return fail(ErrorCode::InvalidArgument,
                    "validate: the asset has " + std::to_string(asset.distances.size()) +
                        " samples for " + std::to_string(asset.pointCount()) + " grid points");
    return {};
}

/// Every grid point in one stratum, or two strata (within 2 voxels of the surface by the
/// asset's own values, and the rest) sampled without replacement.
std::vector<Stratum> choosePoints(const format::ColliderAsset& asset,
                                  const ValidateOptions& options, bool& sampled) {
    const std::uint64_t count = asset.pointCount();
    sampled = count > options.maxFullPoints && options.samplePoints < count;
    if (!sampled) {
        Stratum all;
        all.population = count;
        all.indices.resize(count);
        for (std::uint64_t i = 0; i < count; ++i)
            all.indices[i] = i;
        return {std::move(all)};
    }

    const float band = float(2.0 * asset.meta.voxelSize);
    auto isNear = [&](std::uint64_t i) { return std::abs(asset.distances[i]) < band; };
    std::uint64_t nearCount = 0;
    for (std::uint64_t i = 0; i < count; ++i)
        nearCount += isNear(i) ? 1 : 0;
    const std::uint64_t farCount = count - nearCount;

    // Split the sample by the requested share; a stratum too small to fill its part gives the
    // rest to the other one.
    const std::uint64_t total = options.samplePoints;
    const double share = std::clamp(options.nearSurfaceShare, 0.0, 1.0);
    std::uint64_t wantNear =
        std::min(nearCount, std::uint64_t(std::llround(share * double(total))));
    const std::uint64_t wantFar = std::min(farCount, total - wantNear);
    wantNear = std::min(nearCount, total - wantFar);

    std::vector<Stratum> strata(2);
    strata[0].population = nearCount;
    strata[1].population = farCount;
    strata[0].indices.reserve(wantNear);
    strata[1].indices.reserve(wantFar);
    SelectionSampler nearSampler(nearCount, wantNear, options.seed);
    SelectionSampler farSampler(farCount, wantFar, options.seed ^ 0x5DEECE66Dull);
    for (std::uint64_t i = 0; i < count; ++i) {
        if (isNear(i)) {
            if (nearSampler.take())
                strata[0].indices.push_back(i);
        } else if (farSampler.take()) {
            strata[1].indices.push_back(i);
        }
    }
    return strata;
}

/// Median, 99th percentile and share outside [0.5, 1.5] of |grad phi| by central differences
/// at interior grid points (those with both neighbours along every axis).
void eikonalStatistics(const format::ColliderAsset& asset, format::ValidationFigures& figures) {
    const glm::uvec3 dims = asset.meta.dims;
    if (dims.x < 3 || dims.y < 3 || dims.z < 3)
        return; // no interior points: the figures stay 0
    const std::uint64_t nx = dims.x - 2, ny = dims.y - 2, nz = dims.z - 2;
    std::vector<float> norms(nx * ny * nz);
    const double inv2h = 1.0 / (2.0 * asset.meta.voxelSize);
    const std::uint64_t strideY = dims.x, strideZ = std::uint64_t(dims.x) * dims.y;
    tbb::parallel_for(
        tbb::blocked_range<std::uint64_t>(0, ny * nz),
        [&](const tbb::blocked_range<std::uint64_t>& rows) {
            for (std::uint64_t row = rows.begin(); row != rows.end(); ++row) {
                const std::uint32_t j = std::uint32_t(row % ny) + 1,
                                    k = std::uint32_t(row / ny) + 1;
                for (std::uint32_t i = 1; i + 1 < dims.x; ++i) {
                    const std::uint64_t c = asset.index(i, j, k);
                    const double gx =
                        (double(asset.distances[c + 1]) - asset.distances[c - 1]) * inv2h;
                    const double gy =
                        (double(asset.distances[c + strideY]) - asset.distances[c - strideY]) *
                        inv2h;
                    const double gz =
                        (double(asset.distances[c + strideZ]) - asset.distances[c - strideZ]) *
                        inv2h;
                    norms[row * nx + (i - 1)] = float(std::sqrt(gx * gx + gy * gy + gz * gz));
                }
            }
        });

    const std::uint64_t outside = std::uint64_t(std::count_if(
        norms.begin(), norms.end(), [](float g) { return !(g >= 0.5f && g <= 1.5f); }));
    figures.eikonalOutsideShare = double(outside) / double(norms.size());

    // Nearest-rank percentiles; the median of an even count averages the two middle values.
    const std::size_t n = norms.size();
    const std::size_t mid = (n - 1) / 2;
    std::nth_element(norms.begin(), norms.begin() + std::ptrdiff_t(mid), norms.end());
    double median = norms[mid];
    if (n % 2 == 0)
        median = 0.5 *
                 (median + *std::min_element(norms.begin() + std::ptrdiff_t(mid) + 1, norms.end()));
    figures.eikonalMedian = median;
    const std::size_t p99 = std::size_t(std::ceil(0.99 * double(n))) - 1;
    std::nth_element(norms.begin(), norms.begin() + std::ptrdiff_t(p99), norms.end());
    figures.eikonalP99 = norms[p99];
}

/// [world units] The positions of the grid points of linear `indices` (x fastest).
std::vector<glm::dvec3> pointsAt(const format::ColliderAsset& asset,
                                 const std::vector<std::uint64_t>& indices) {
    std::vector<glm::dvec3> points(indices.size());
    const glm::uvec3 dims = asset.meta.dims;
    for (std::size_t n = 0; n < indices.size(); ++n) {
        const std::uint64_t idx = indices[n];
        const std::uint32_t i = std::uint32_t(idx % dims.x);
        const std::uint32_t j = std::uint32_t((idx / dims.x) % dims.y);
        const std::uint32_t k = std::uint32_t(idx / (std::uint64_t(dims.x) * dims.y));
        points[n] = asset.pointPosition(i, j, k);
    }
    return points;
}

/// The error and sign figures of the strata against the reference, into `report`.
///
/// Sums per stratum in index order (deterministic), then weights each stratum by its share of
/// the grid: the stratified estimates of mean, RMS and mismatch percentage are unbiased for the
/// whole grid even though the sample over-represents the surface. Max and the counts are over
/// the points actually checked. A stratum left empty (a share of 0 or 1) drops out, and the
/// weights are renormalized.
void compareStrata(const format::ColliderAsset& asset, const std::vector<Stratum>& strata,
                   const CgalReference& reference, const ValidateOptions& options,
                   Progress* progress, ValidationReport& report) {
    const double h = asset.meta.voxelSize;
    const double band = options.surfaceBand * h;
    format::ValidationFigures& figures = report.figures;
    double mean = 0.0, meanSquare = 0.0, mismatchShare = 0.0;
    double weightTaken = 0.0, weightCompared = 0.0;
    const double gridPoints = double(asset.pointCount());
    for (const Stratum& stratum : strata) {
        if (stratum.indices.empty())
            continue;
        const std::vector<double> exact =
            reference.signedDistances(pointsAt(asset, stratum.indices), progress);
        detail::PointComparison c;
        for (std::size_t n = 0; n < exact.size(); ++n) {
            const float phi = asset.distances[stratum.indices[n]];
            c.addError(phi, exact[n], h, figures.maxError);
            c.addSign(phi, exact[n], band);
        }
        const double weight = double(stratum.population) / gridPoints;
        const double taken = double(exact.size());
        mean += weight * c.sum / taken;
        meanSquare += weight * c.sumSquare / taken;
        weightTaken += weight;
        if (c.compared > 0) {
            mismatchShare += weight * double(c.mismatches) / double(c.compared);
            weightCompared += weight;
        }
        figures.pointsChecked += exact.size();
        figures.signMismatches += c.mismatches;
        report.signComparedPoints += c.compared;
    }
    if (weightTaken > 0.0) {
        figures.meanError = mean / weightTaken;
        figures.rmsError = std::sqrt(meanSquare / weightTaken);
    }
    if (weightCompared > 0.0)
        report.signMismatchPercent = 100.0 * mismatchShare / weightCompared;
}

} // namespace

Result<ValidationReport> validate(const format::ColliderAsset& asset, const ImportedMesh& mesh,
                                  const ValidateOptions& options, Progress* progress) {
    if (Result<void> ok = checkAsset(asset); !ok)
        return ok.error();
    Result<CgalReference> reference =
        CgalReference::build(mesh.soup, mesh.diagnostics, options.sign);
    if (!reference)
        return reference.error();

    if (asset.sparse())
        return detail::validateSparse(asset, *reference, options, progress);

    ValidationReport report;
    report.referenceSign = reference->signMethod();
    const std::vector<Stratum> strata = choosePoints(asset, options, report.sampled);
    compareStrata(asset, strata, *reference, options, progress, report);
    eikonalStatistics(asset, report.figures);
    report.figures.known = true;
    return report;
}

} // namespace sluice::bake
