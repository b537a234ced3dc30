// Sparse bakes on the CPU with the CGAL reference: culling with the AABB tree's exact distances,
// then exact signed distances at every band brick voxel (SparseBaker.cpp has the steps).
#include "sluice/bake/cgal/CgalSparseBaker.h"

#include <algorithm>
#include <chrono>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "BakeErrors.h"
#include "cgal/CgalBakeStart.h"
#include "sluice/bake/jobs/PhaseLog.h"
#include "sluice/bake/jobs/Progress.h"
#include "sparse/SparseBricks.h"

namespace sluice::bake {

namespace {

/// Bricks per batch of exact distances: 2^20 voxels, 24 MB of positions.
constexpr std::size_t kBricksPerBatch = 2048;

/// The band bricks and uniform blocks, culled with the reference's exact unsigned distances.
SparsePlan planWithReference(const GridSpec& grid, double band, const CgalReference& reference,
                             SparseBakeStats& stats) {
    const auto start = std::chrono::steady_clock::now();
    const SparsePlan plan =
        planSparse(grid, band, [&](std::span<const glm::dvec3> p, std::span<double> d) {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, p.size(), 64),
                              [&](const tbb::blocked_range<std::size_t>& r) {
                                  for (std::size_t n = r.begin(); n != r.end(); ++n)
                                      d[n] = reference.unsignedDistance(p[n]);
                              });
        });
    recordPlan(plan, secondsSince(start), stats);
    return plan;
}

/// [world units] The exact signed distances of one batch of bricks, kBrickVoxels per brick
/// (x fastest), 0 outside the domain; counts the computed ones in stats.voxelsComputed.
std::vector<float> brickValues(const GridSpec& grid, std::span<const glm::ivec3> bricks,
                               const CgalReference& reference, Progress& bar,
                               SparseBakeStats& stats) {
    std::vector<glm::dvec3> points;
    std::vector<std::uint32_t> slots; // brick voxel each point fills
    for (std::size_t b = 0; b < bricks.size(); ++b)
        for (std::uint32_t v = 0; v < kBrickVoxels; ++v) {
            const glm::ivec3 p = bricks[b] + brickVoxel(v);
            if (!insideDomain(p, grid.dims))
                continue;
            points.push_back(grid.origin + glm::dvec3(p) * grid.voxelSize);
            slots.push_back(std::uint32_t(b * kBrickVoxels + v));
        }
    const std::vector<double> phi = reference.signedDistances(points, &bar);
    std::vector<float> values(bricks.size() * kBrickVoxels, 0.0f);
    for (std::size_t n = 0; n < phi.size(); ++n)
        values[slots[n]] = float(phi[n]);
    stats.voxelsComputed += points.size();
    return values;
}

/// The band bricks into `builder`, kBricksPerBatch at a time. Returns the seconds spent in the
/// builder.
double addBandBricks(SparseGridBuilder& builder, const GridSpec& grid, const SparsePlan& plan,
                     const CgalReference& reference, Progress& bar, SparseBakeStats& stats) {
    double buildSeconds = 0.0;
    for (std::size_t b0 = 0; b0 < plan.bricks.size(); b0 += kBricksPerBatch) {
        const std::span<const glm::ivec3> bricks =
            std::span(plan.bricks).subspan(b0, std::min(kBricksPerBatch, plan.bricks.size() - b0));
        const std::vector<float> values = brickValues(grid, bricks, reference, bar, stats);
        const auto buildStart = std::chrono::steady_clock::now();
        builder.addBricks(bricks, values);
        buildSeconds += secondsSince(buildStart);
    }
    return buildSeconds;
}

Result<format::ColliderAsset> bakeSparseChecked(const ImportedMesh& mesh,
                                                const BakeSettings& settings,
                                                const SparseSettings& sparse, bool showProgress,
                                                SparseBakeStats& stats) {
    Result<CgalBakeStart> start = startCgalBake(
        mesh, sparseGridFor(mesh.soup.bounds(), settings.grid, sparse.band), settings.sign);
    if (!start)
        return start.error();
    const GridSpec& grid = start->grid;
    const CgalReference& reference = start->reference;
    const SparsePlan plan = planWithReference(grid, sparse.band, reference, stats);
    Progress bar("baking " + mesh.sourceFile + " (sparse band)",
                 std::uint64_t(plan.bricks.size()) * kBrickVoxels, showProgress);

    const auto distanceStart = std::chrono::steady_clock::now();
    SparseGridBuilder builder(grid, sparse.band);
    const double buildSeconds = addBandBricks(builder, grid, plan, reference, bar, stats);
    // One sample per uniform block: no surface within it, so its centre's sign is its sign.
    const std::vector<double> blockPhi = reference.signedDistances(blockCentres(grid, plan));
    stats.distanceSeconds = secondsSince(distanceStart) - buildSeconds;
    bar.finish();

    stats.buildSeconds = buildSeconds;
    return finishSparseAsset(
        builder, plan, blockPhi,
        sparseProvenance(mesh, grid, settings, "cgal", reference.signMethod(), sparse.band), stats);
}

} // namespace

Result<format::ColliderAsset> bakeSparseCgal(const ImportedMesh& mesh, const BakeSettings& settings,
                                             const SparseSettings& sparse, bool showProgress,
                                             SparseBakeStats* stats) {
    SparseBakeStats local;
    return withCgalErrors(mesh, [&] {
        return bakeSparseChecked(mesh, settings, sparse, showProgress, stats ? *stats : local);
    });
}

} // namespace sluice::bake
