// Sparse bakes on the GPU: the GPU bake's passes (GpuBaker.cpp describes them) over lists of
// points and bricks instead of the whole grid; SparseGridBuilder makes the NanoVDB grid.
//
//   1. Culling (planSparse): each level's block centres go through the coarse distance pass over
//      query points (SDF_POINTS). Each distance is understated by a bound on its float rounding,
//      so the culling keeps every brick the exact distances would.
//   2. The uniform blocks' centres: distance, then sign (the coarse sign pass, SDF_POINTS).
//   3. The band bricks, GpuBakeOptions::sparseBricksPerBatch at a time (SDF_SPARSE): the coarse
//      pass over each brick's 27 coarse points and (closed soups) the sign of each distinct one
//      (neighbouring bricks share them), the fine pass over the bricks in slabs with the sign
//      passes after each, as the dense bake runs them; then the batch is read back, turned into
//      world units and added to the builder.
// Work and GPU memory grow with the band: the buffers are sized for one batch, whatever the grid.
#include "sluice/bake/gpu/GpuSparseBaker.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gpu/GpuBakePasses.h"
#include "sparse/SparseBricks.h"

namespace sluice::bake {

namespace {

static_assert(kBrickSize == std::uint32_t(shared::kBakeBrickSize), "a brick is one NanoVDB leaf");
/// Query points per dispatch of the culling.
constexpr std::uint32_t kQueriesPerBatch = std::uint32_t(1) << 18;
/// Bricks per work group of the fine pass, and fine-pass work groups of the first slab (2^18
/// points, as the dense bake's).
constexpr std::uint32_t kBricksPerGroup =
    shared::kBakeLocalSize * 4 * shared::kBakeBlockDepth / kBrickVoxels;
constexpr std::uint32_t kFirstSlabGroups = 256;
/// Coarse points per brick, and invocations of the sparse coarse pass per brick.
constexpr std::uint32_t kBrickCoarsePoints =
    shared::kBakeBrickCoarse * shared::kBakeBrickCoarse * shared::kBakeBrickCoarse;
constexpr std::uint32_t kCoarseInvocationsPerBrick = 4;
/// A GPU distance's float rounding is below 4e-3 voxel for coordinates up to kMaxGpuSparseAxis
/// voxels (half an ulp of each coordinate, and of each triangle corner); culling takes off more.
constexpr double kQueryMarginVoxels = 0.01;
constexpr std::uint32_t kMaxGpuSparseAxis = 16384;
constexpr double kQueryMarginRelative = 1e-5;

/// Where the fine pass leaves point i (0..511) of a brick: block slot i / 16 (Morton order of
/// the brick's 4 x 4 x 2 blocks), point i % 16 of the block; as the index of that point in the
/// brick, x fastest.
std::array<std::uint16_t, kBrickVoxels> brickPointOrder() {
    std::array<std::uint16_t, kBrickVoxels> order{};
    const std::uint32_t blockPoints = 4 * shared::kBakeBlockDepth;
    for (std::uint32_t i = 0; i < kBrickVoxels; ++i) {
        const std::uint32_t m = i / blockPoints, k = i % blockPoints;
        const glm::uvec3 block((m & 1) | ((m >> 2) & 2), ((m >> 1) & 1) | ((m >> 3) & 2),
                               ((m >> 2) & 1) | ((m >> 4) & 2));
        const glm::uvec3 p = block * glm::uvec3(2, 2, shared::kBakeBlockDepth) +
                             glm::uvec3(k & 1, (k >> 1) & 1, k >> 2);
        order[i] = std::uint16_t(p.x + kBrickSize * (p.y + kBrickSize * p.z));
    }
    return order;
}

/// The sparse bake's GPU buffers, sized for one batch, on their bindings.
struct SparseBuffers {
    gpu::Buffer list;      ///< bricks (uvec4) or query points (vec4)
    gpu::Buffer phi;       ///< distances of a batch of bricks [voxels]
    gpu::Buffer coarse;    ///< CoarsePoint per brick coarse point or query point
    gpu::Buffer pending;   ///< PendingHeader, then the blocks of a slab still without a sign
    gpu::Buffer verify;    ///< PendingHeader, then the points of a slab for the exact sum
    gpu::Buffer coarseRep; ///< first coarse entry at each entry's point, then the distinct ones

    std::uint64_t bytes() const {
        return list.size() + phi.size() + coarse.size() + pending.size() + verify.size() +
               coarseRep.size();
    }
};

/// For each coarse entry of `corners` (kBrickCoarsePoints per brick), the first entry at the
/// same grid point, then the list of those first entries (shared/SdfBake.h, coarseRep).
/// Neighbouring bricks share their faces' coarse points, so a sheet of bricks has about a third
/// as many distinct points as entries.
std::vector<std::uint32_t> coarseRepresentatives(std::span<const glm::ivec3> corners,
                                                 glm::uvec3 dims) {
    const std::uint32_t entries = std::uint32_t(corners.size()) * kBrickCoarsePoints;
    const std::uint32_t side = shared::kBakeBrickCoarse;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(entries);
    for (std::uint32_t e = 0; e < entries; ++e) {
        const std::uint32_t c = e % kBrickCoarsePoints;
        const glm::uvec3 offset(c % side, (c / side) % side, c / (side * side));
        const glm::uvec3 p = glm::min(glm::uvec3(corners[e / kBrickCoarsePoints]) +
                                          offset * std::uint32_t(shared::kBakeCoarseSpacing),
                                      dims - 1u);
        keyed[e] = {std::uint64_t(p.x) | std::uint64_t(p.y) << 21 | std::uint64_t(p.z) << 42, e};
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t> out(entries);
    std::vector<std::uint32_t> distinct;
    for (std::size_t n = 0; n < keyed.size(); ++n) {
        if (n == 0 || keyed[n].first != keyed[n - 1].first)
            distinct.push_back(keyed[n].second); // the lowest entry: pairs sort by it second
        out[keyed[n].second] = distinct.back();
    }
    std::sort(distinct.begin(), distinct.end());
    out.insert(out.end(), distinct.begin(), distinct.end());
    return out;
}

Result<SparseBuffers> createSparseBuffers(const ImportedMesh& mesh, gpu::Context& context,
                                          const GpuBakeOptions& options,
                                          std::uint32_t bricksPerBatch) {
    const std::uint64_t blocks =
        std::uint64_t(bricksPerBatch) * kBrickVoxels / (4 * shared::kBakeBlockDepth);
    SparseBuffers b;
    const StorageAlloc allocs[] = {
        {&b.list, std::uint64_t(std::max(bricksPerBatch, kQueriesPerBatch)) * sizeof(glm::uvec4),
         "sparse bake bricks / query points", shared::kBakeBrickBinding},
        {&b.phi, std::uint64_t(bricksPerBatch) * kBrickVoxels * sizeof(float),
         "sparse bake distances", shared::kBakeDistanceBinding},
        {&b.coarse,
         std::uint64_t(std::max(bricksPerBatch * kBrickCoarsePoints, kQueriesPerBatch)) *
             sizeof(shared::CoarsePoint),
         "sparse bake coarse points", shared::kBakeCoarseBinding},
        {&b.pending, pendingBytes(blocks), "sparse bake pending blocks",
         shared::kBakePendingBinding},
        {&b.verify, verifyBytes(blocks), "sparse bake verify points", shared::kBakeVerifyBinding},
        {&b.coarseRep,
         2 * std::uint64_t(bricksPerBatch) * kBrickCoarsePoints * sizeof(std::uint32_t),
         "sparse bake coarse representatives", shared::kBakeCoarseRepBinding},
    };
    const std::uint64_t maxBuffer =
        options.maxBufferBytes > 0 ? options.maxBufferBytes : context.info().maxSsboBytes;
    std::uint64_t total = 0;
    for (const StorageAlloc& a : allocs) {
        total += a.bytes;
        if (a.bytes > maxBuffer)
            return fail(ErrorCode::SizeOverflow,
                        mesh.sourceFile + ": the sparse bake needs a " + mib(a.bytes) +
                            " GPU buffer, over this GPU's largest storage buffer (" +
                            mib(maxBuffer) + "); use --backend cgal");
    }
    if (const auto& available = context.info().gpuMemoryAvailableBytes;
        available && total > *available)
        return fail(ErrorCode::GpuOutOfMemory,
                    mesh.sourceFile + ": the sparse bake needs " + mib(total) +
                        " of GPU memory and " + mib(*available) + " are free; use --backend cgal");
    if (Result<void> created = createStorage(allocs); !created)
        return created.error();
    return b;
}

/// The bake's state on the GPU: programs, buffers and passes.
struct SparseGpu {
    const GridSpec& grid;
    BakePrograms& points; ///< SDF_POINTS
    BakePrograms& bricks; ///< SDF_SPARSE
    SparseBuffers& buffers;
    BakePasses& passes;
    std::uint32_t bricksPerBatch;

    /// Distances [world units] of `world` points, signed (negative inside) with `sign`, else
    /// unsigned and understated by their float rounding bound.
    void query(std::span<const glm::dvec3> world, std::span<double> out, bool sign) {
        std::vector<glm::vec4> voxels;
        for (std::size_t q0 = 0; q0 < world.size(); q0 += kQueriesPerBatch) {
            const auto n =
                std::uint32_t(std::min<std::size_t>(kQueriesPerBatch, world.size() - q0));
            voxels.resize(n);
            for (std::uint32_t i = 0; i < n; ++i)
                voxels[i] = glm::vec4((world[q0 + i] - grid.origin) / grid.voxelSize, 0.0);
            buffers.list.upload(voxels);
            points.coarse.set("itemCount", n);
            passes.distance(points.coarse,
                            glm::uvec3(gpu::groupCount(n, shared::kBakeLocalSize), 1, 1));
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            if (sign) {
                passes.sign(points.coarseSign, n, passes.maxGroups);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            }
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            const std::vector<shared::CoarsePoint> result =
                buffers.coarse.download<shared::CoarsePoint>(0, n);
            for (std::uint32_t i = 0; i < n; ++i) {
                const double d = result[i].distance;
                out[q0 + i] =
                    sign ? d * grid.voxelSize
                         : std::max(0.0, d - kQueryMarginVoxels - kQueryMarginRelative * d) *
                               grid.voxelSize;
            }
        }
    }

    /// Exact signed distances [voxels] of `count` bricks from `corners`, into `phi` (brick after
    /// brick, each x fastest). Progress after every slab.
    void bakeBricks(std::span<const glm::ivec3> corners, bool propagate, std::vector<float>& phi,
                    Progress* progress) {
        const auto n = std::uint32_t(corners.size());
        std::vector<glm::uvec4> list(n);
        for (std::uint32_t b = 0; b < n; ++b)
            list[b] = glm::uvec4(glm::uvec3(corners[b]), 0u);
        buffers.list.upload(list);
        const std::vector<std::uint32_t> reps = coarseRepresentatives(corners, grid.dims);
        buffers.coarseRep.upload(reps);
        const auto distinct = std::uint32_t(reps.size()) - n * kBrickCoarsePoints;
        for (const gpu::Program* program : {&bricks.coarse, &bricks.distance, &bricks.coarseSign,
                                            &bricks.sign, &bricks.exactSign})
            program->set("brickCount", n);
        passes.distance(bricks.coarse,
                        glm::uvec3(gpu::groupCount(n * kCoarseInvocationsPerBrick,
                                                   std::uint32_t(shared::kBakeLocalSize)),
                                   1, 1));
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        if (propagate) {
            passes.sign(bricks.coarseSign, distinct, passes.maxGroups);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        }
        SlabPlan plan;
        plan.layers = (n + kBricksPerGroup - 1) / kBricksPerGroup;
        plan.firstLayers =
            std::min({kFirstSlabGroups, plan.layers, bricksPerBatch / kBricksPerGroup});
        plan.maxLayers = std::max(plan.firstLayers, bricksPerBatch / kBricksPerGroup);
        plan.alongX = true;
        plan.pointsOf = [n](std::uint32_t g0, std::uint32_t g1) {
            return std::uint64_t(std::min(n, g1 * kBricksPerGroup) - g0 * kBricksPerGroup) *
                   kBrickVoxels;
        };
        runSlabs(passes, bricks, {buffers.pending, buffers.verify}, plan, progress);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        const std::vector<float> slots =
            buffers.phi.download<float>(0, std::size_t(n) * kBrickVoxels);
        static const std::array<std::uint16_t, kBrickVoxels> order = brickPointOrder();
        phi.resize(slots.size());
        for (std::size_t b = 0; b < n; ++b)
            for (std::uint32_t i = 0; i < kBrickVoxels; ++i)
                phi[b * kBrickVoxels + order[i]] = slots[b * kBrickVoxels + i];
    }
};

/// Grid points of the brick at `corner` inside the domain [0, dims).
std::uint64_t pointsInDomain(const glm::ivec3& corner, const glm::uvec3& dims) {
    std::uint64_t points = 1;
    for (int a = 0; a < 3; ++a)
        points *= std::uint64_t(
            std::clamp<std::int64_t>(std::int64_t(dims[a]) - corner[a], 0, kBrickSize));
    return points;
}

/// SizeOverflow when the grid is longer than the GPU bake's float coordinates hold exactly
/// enough (kMaxGpuSparseAxis).
Result<void> checkSparseAxis(const GridSpec& grid, const ImportedMesh& mesh) {
    const std::uint32_t longest = std::max({grid.dims.x, grid.dims.y, grid.dims.z});
    if (longest > kMaxGpuSparseAxis)
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": a sparse grid " + std::to_string(longest) +
                        " points long is over the GPU bake's " + std::to_string(kMaxGpuSparseAxis) +
                        " (float coordinates); use a coarser voxel size or --backend cgal");
    return {};
}

/// The band bricks and uniform blocks, culled with the GPU's understated distances.
SparsePlan planOnGpu(SparseGpu& sparseGpu, double band, SparseBakeStats& stats, PhaseLog* phases) {
    const auto start = std::chrono::steady_clock::now();
    const SparsePlan plan =
        planSparse(sparseGpu.grid, band, [&](std::span<const glm::dvec3> p, std::span<double> d) {
            sparseGpu.query(p, d, false);
        });
    recordPlan(plan, secondsSince(start), stats);
    lap(phases, "gpu: culling (band bricks)");
    return plan;
}

/// [world units] The signed distance at each uniform block's centre: no surface within the
/// block, so its centre's sign is its own. Adds the time to stats.distanceSeconds.
std::vector<double> signBlocks(SparseGpu& sparseGpu, const SparsePlan& plan, SparseBakeStats& stats,
                               PhaseLog* phases) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<glm::dvec3> centres = blockCentres(sparseGpu.grid, plan);
    std::vector<double> blockPhi(centres.size());
    sparseGpu.query(centres, blockPhi, true);
    stats.distanceSeconds += secondsSince(start);
    lap(phases, "gpu: uniform blocks' signs");
    return blockPhi;
}

/// The band bricks, a batch at a time: the passes, then the values in world units into
/// `builder`. Adds the GPU's time to stats.distanceSeconds, the builder's to buildSeconds.
void addBandBricks(SparseGpu& sparseGpu, SparseGridBuilder& builder, const SparsePlan& plan,
                   bool propagate, Progress& bar, SparseBakeStats& stats) {
    std::vector<float> phi;
    std::vector<float> values;
    const std::size_t batch = sparseGpu.bricksPerBatch;
    for (std::size_t b0 = 0; b0 < plan.bricks.size(); b0 += batch) {
        auto start = std::chrono::steady_clock::now();
        const std::span<const glm::ivec3> corners =
            std::span(plan.bricks).subspan(b0, std::min(batch, plan.bricks.size() - b0));
        sparseGpu.bakeBricks(corners, propagate, phi, &bar);
        stats.distanceSeconds += secondsSince(start);
        start = std::chrono::steady_clock::now();
        // Voxels to world units in double, so the only float rounding is the GPU's and the last.
        values.resize(phi.size());
        std::transform(phi.begin(), phi.end(), values.begin(),
                       [&](float v) { return float(double(v) * sparseGpu.grid.voxelSize); });
        for (const glm::ivec3& corner : corners)
            stats.voxelsComputed += pointsInDomain(corner, sparseGpu.grid.dims);
        builder.addBricks(corners, values);
        stats.buildSeconds += secondsSince(start);
    }
}

Result<format::ColliderAsset> bakeSparseChecked(const ImportedMesh& mesh,
                                                const BakeSettings& settings,
                                                const SparseSettings& sparse, gpu::Context& context,
                                                bool showProgress, const GpuBakeOptions& options,
                                                GpuBakeStats& stats, SparseBakeStats& sparseStats) {
    Result<GridSpec> grid = sparseGridFor(mesh.soup.bounds(), settings.grid, sparse.band);
    if (!grid)
        return grid.error();
    if (Result<void> axis = checkSparseAxis(*grid, mesh); !axis)
        return axis.error();
    const auto fits = [&](std::uint64_t triangles) {
        return checkBvhFits(mesh.sourceFile, triangles, options);
    };
    Result<BakeSetup> setup = setUpBake(
        mesh, *grid, settings.sign, {BakeLayout::Points, BakeLayout::Sparse}, fits, options, stats);
    if (!setup)
        return setup.error();
    const std::uint32_t bricksPerBatch =
        std::clamp<std::uint32_t>(options.sparseBricksPerBatch, kBricksPerGroup, 1u << 16);
    Result<SparseBuffers> buffers = createSparseBuffers(mesh, context, options, bricksPerBatch);
    if (!buffers)
        return buffers.error();
    stats.gpuBytes = setup->gpuBvh.bytes() + buffers->bytes();
    lap(options.phases, "gpu: upload");

    BakePasses passes = makePasses(stats, options, setup->bvh.triangleCount);
    BakePrograms& points = setup->programs[0]; // SDF_POINTS
    BakePrograms& bricks = setup->programs[1]; // SDF_SPARSE
    SparseGpu sparseGpu{*grid, points, bricks, *buffers, passes, bricksPerBatch};
    const SparsePlan plan = planOnGpu(sparseGpu, sparse.band, sparseStats, options.phases);
    const std::vector<double> blockPhi = signBlocks(sparseGpu, plan, sparseStats, options.phases);
    Progress bar("baking " + mesh.sourceFile + " on the GPU (sparse band)",
                 std::uint64_t(plan.bricks.size()) * kBrickVoxels, showProgress);
    SparseGridBuilder builder(*grid, sparse.band);
    // As in the dense bake, a closed soup's points may take the sign of a coarse point's ball.
    addBandBricks(sparseGpu, builder, plan, setup->soup.cycle, bar, sparseStats);
    bar.finish();
    passes.readTimes();
    lap(options.phases, "gpu: band bricks (passes, readback, leaves)");

    Result<format::ColliderAsset> asset = finishSparseAsset(
        builder, plan, blockPhi,
        sparseProvenance(mesh, *grid, settings, "gpu", setup->soup.method, sparse.band),
        sparseStats);
    lap(options.phases, "gpu: NanoVDB grid and asset (provenance, mass properties)");
    return asset;
}

} // namespace

Result<format::ColliderAsset> bakeSparseGpu(const ImportedMesh& mesh, const BakeSettings& settings,
                                            const SparseSettings& sparse, gpu::Context& context,
                                            bool showProgress, const GpuBakeOptions& options,
                                            GpuBakeStats* stats, SparseBakeStats* sparseStats) {
    context.makeCurrent();
    GpuBakeStats localStats;
    SparseBakeStats localSparse;
    if (stats)
        *stats = {};
    if (sparseStats)
        *sparseStats = {};
    return withGpuBakeErrors(mesh, [&] {
        return bakeSparseChecked(mesh, settings, sparse, context, showProgress, options,
                                 stats ? *stats : localStats,
                                 sparseStats ? *sparseStats : localSparse);
    });
}

} // namespace sluice::bake
