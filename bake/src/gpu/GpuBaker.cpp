// Baking a collider asset on the GPU: CPU BVH, then coarse, fine and sign passes in GL compute.
//
// The soup is prepared as the CGAL reference prepares it (GpuSoup.h), then moved into
// grid-relative voxel coordinates, where grid point (i, j, k) is the float (i, j, k) and every
// coordinate is no larger than the grid.
//
// Passes (shaders/bake/sdf_*.comp):
//   1. coarse distance: the nearest triangle of every 4th grid point along each axis;
//   2. coarse sign: their fast winding number (closed soups only);
//   3. fine distance, in z-slabs: exact distances, each invocation a block of 2 x 2 x 4 points
//      starting from the coarse triangles around it; a point inside a coarse point's empty ball
//      takes its sign (closed soups), blocks with other points go to a pending list;
//   4. after each slab, the fast winding number of the pending points, block by block, and the
//      exact one of the few too near the decision value.
// Every pass is split into dispatches of a bounded number of work groups; the CPU reads back two
// counters per slab and nothing else until the end.
#include "sluice/bake/gpu/GpuBaker.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gpu/GpuBakePasses.h"

namespace sluice::bake {

namespace {

/// Slabs of the fine pass (runSlabs): the first has about kFirstSlabPoints points, later ones up
/// to kMaxSlabPoints (the lists' room).
constexpr std::uint64_t kFirstSlabPoints = std::uint64_t(1) << 18;
constexpr std::uint64_t kMaxSlabPoints = std::uint64_t(1) << 22;

/// Sizes of the bake's GPU buffers [bytes], known before anything is built.
struct BakeSizes {
    glm::uvec3 coarseDims{0};        ///< [coarse points]
    std::uint32_t slabGroups = 0;    ///< z layers of work groups in the first slab
    std::uint32_t maxSlabGroups = 0; ///< z layers of work groups the lists have room for
    std::uint64_t grid = 0;          ///< phi
    std::uint64_t coarse = 0;        ///< CoarsePoint per coarse point
    std::uint64_t pending = 0;       ///< PendingHeader + one entry per block of a slab
    std::uint64_t verify = 0;        ///< PendingHeader + one entry per grid point of a slab
    std::uint64_t triangles = 0;     ///< triangle texels
    std::uint64_t nodes = 0;         ///< one of the two node textures (an upper bound)

    std::uint64_t total() const { return grid + coarse + pending + verify + triangles + 2 * nodes; }
};

BakeSizes bakeSizes(glm::uvec3 dims, std::uint64_t triangles) {
    BakeSizes sizes;
    const std::uint32_t spacing = shared::kBakeCoarseSpacing;
    sizes.coarseDims = (dims + spacing - 2u) / spacing + 1u;
    const std::uint64_t groupDepth = shared::kBakeGroupDepth;
    const std::uint64_t groupLayer = std::uint64_t(dims.x) * dims.y * groupDepth;
    const std::uint64_t groupLayers = (dims.z + groupDepth - 1) / groupDepth;
    sizes.slabGroups =
        std::uint32_t(std::clamp<std::uint64_t>(kFirstSlabPoints / groupLayer, 1, groupLayers));
    sizes.maxSlabGroups = std::uint32_t(
        std::clamp<std::uint64_t>(kMaxSlabPoints / groupLayer, sizes.slabGroups, groupLayers));
    sizes.grid = std::uint64_t(dims.x) * dims.y * dims.z * sizeof(float);
    sizes.coarse = std::uint64_t(sizes.coarseDims.x) * sizes.coarseDims.y * sizes.coarseDims.z *
                   sizeof(shared::CoarsePoint);
    // Blocks of a slab: the invocations of its work groups.
    const std::uint64_t groupsPerLayer =
        std::uint64_t((dims.x + shared::kBakeGroupEdge - 1) / shared::kBakeGroupEdge) *
        ((dims.y + shared::kBakeGroupEdge - 1) / shared::kBakeGroupEdge);
    const std::uint64_t slabBlocks = sizes.maxSlabGroups * groupsPerLayer * shared::kBakeLocalSize;
    sizes.pending = pendingBytes(slabBlocks);
    sizes.verify = verifyBytes(slabBlocks);
    sizes.triangles = bvhTriangleBytes(triangles);
    sizes.nodes = bvhNodeBytes(triangles);
    return sizes;
}

/// SizeOverflow or GpuOutOfMemory when the bake's buffers cannot exist on this GPU.
Result<void> checkSizes(const BakeSizes& sizes, const ImportedMesh& mesh, glm::uvec3 dims,
                        std::uint64_t triangles, gpu::Context& context,
                        const GpuBakeOptions& options) {
    const std::uint64_t maxBuffer =
        options.maxBufferBytes > 0 ? options.maxBufferBytes : context.info().maxSsboBytes;
    const std::uint64_t largest = std::max({sizes.grid, sizes.coarse, sizes.pending, sizes.verify});
    if (largest > maxBuffer)
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": a grid of " + std::to_string(dims.x) + " x " +
                        std::to_string(dims.y) + " x " + std::to_string(dims.z) +
                        " points needs a " + mib(largest) +
                        " GPU buffer, over this GPU's largest storage buffer (" + mib(maxBuffer) +
                        "); use a coarser resolution or --backend cgal");
    if (Result<void> fits = checkBvhFits(mesh.sourceFile, triangles, options); !fits)
        return fits;
    if (const auto& available = context.info().gpuMemoryAvailableBytes;
        available && sizes.total() > *available)
        return fail(ErrorCode::GpuOutOfMemory,
                    mesh.sourceFile + ": the bake needs " + mib(sizes.total()) +
                        " of GPU memory and " + mib(*available) +
                        " are free; use a coarser resolution or --backend cgal");
    return {};
}

/// The grid's work buffers, on their bindings.
struct GridBuffers {
    gpu::Buffer phi;     ///< distance per grid point [voxels]
    gpu::Buffer coarse;  ///< CoarsePoint per coarse point
    gpu::Buffer pending; ///< PendingHeader, then the blocks of a slab still without a sign
    gpu::Buffer verify;  ///< PendingHeader, then the points of a slab for the exact sum

    std::uint64_t bytes() const {
        return phi.size() + coarse.size() + pending.size() + verify.size();
    }
};

Result<GridBuffers> createGridBuffers(const BakeSizes& sizes) {
    GridBuffers b;
    const StorageAlloc allocs[] = {
        {&b.phi, sizes.grid, "bake distances", shared::kBakeDistanceBinding},
        {&b.coarse, sizes.coarse, "bake coarse points", shared::kBakeCoarseBinding},
        {&b.pending, sizes.pending, "bake pending blocks", shared::kBakePendingBinding},
        {&b.verify, sizes.verify, "bake verify points", shared::kBakeVerifyBinding},
    };
    if (Result<void> created = createStorage(allocs); !created)
        return created.error();
    return b;
}

/// Grid points per work group of the distance passes.
const glm::uvec3 kGroupPoints(shared::kBakeGroupEdge, shared::kBakeGroupEdge,
                              shared::kBakeGroupDepth);

/// Passes 1 and 2: the coarse points' nearest triangles, then (where the sign propagates) their
/// signs.
void runCoarsePasses(BakePasses& passes, const BakePrograms& programs, glm::uvec3 coarseDims,
                     bool propagate) {
    passes.distance(programs.coarse, gpu::groupCount(coarseDims, kGroupPoints));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    if (propagate) {
        passes.sign(programs.coarseSign, coarseDims.x * coarseDims.y * coarseDims.z,
                    passes.maxGroups);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
}

/// Passes 3 and 4 over the grid in z-slabs of work groups.
void runGridSlabs(BakePasses& passes, const BakePrograms& programs, GridBuffers& buffers,
                  const BakeSizes& sizes, glm::uvec3 dims, Progress* progress) {
    const glm::uvec3 groups = gpu::groupCount(dims, kGroupPoints);
    const std::uint64_t slice = std::uint64_t(dims.x) * dims.y;
    SlabPlan plan;
    plan.layerGroups = glm::uvec2(groups.x, groups.y);
    plan.layers = groups.z;
    plan.firstLayers = sizes.slabGroups;
    plan.maxLayers = sizes.maxSlabGroups;
    plan.pointsOf = [&](std::uint32_t z0, std::uint32_t z1) {
        const std::uint32_t groupDepth = shared::kBakeGroupDepth;
        const std::uint32_t k0 = z0 * groupDepth, k1 = std::min(dims.z, z1 * groupDepth);
        return std::uint64_t(k1 - k0) * slice;
    };
    runSlabs(passes, programs, {buffers.pending, buffers.verify}, plan, progress);
}

/// The asset of the baked grid, `voxels` in grid-relative voxel units.
format::ColliderAsset makeAsset(const ImportedMesh& mesh, const GridSpec& grid,
                                const BakeSettings& settings, format::SignMethod method,
                                const std::vector<float>& voxels) {
    format::ColliderAsset asset;
    asset.meta = bakeProvenance(mesh, grid, settings, "gpu", method);
    // Voxels to world units in double, so the only float rounding is the GPU's and the last one.
    asset.distances.resize(voxels.size());
    std::transform(voxels.begin(), voxels.end(), asset.distances.begin(),
                   [&](float v) { return float(double(v) * grid.voxelSize); });
    return asset;
}

Result<format::ColliderAsset> bakeChecked(const ImportedMesh& mesh, const BakeSettings& settings,
                                          gpu::Context& context, Progress* progress,
                                          const GpuBakeOptions& options, GpuBakeStats& stats) {
    Result<GridSpec> grid = gridFor(mesh.soup.bounds(), settings.grid);
    if (!grid)
        return grid.error();
    const glm::uvec3 dims = grid->dims;
    const auto fits = [&](std::uint64_t triangles) {
        return checkSizes(bakeSizes(dims, triangles), mesh, dims, triangles, context, options);
    };
    Result<BakeSetup> setup =
        setUpBake(mesh, *grid, settings.sign, {BakeLayout::Dense}, fits, options, stats);
    if (!setup)
        return setup.error();
    const BakeSizes sizes = bakeSizes(dims, setup->soup.triangles.size());
    Result<GridBuffers> buffers = createGridBuffers(sizes);
    if (!buffers)
        return buffers.error();
    stats.gpuBytes = setup->gpuBvh.bytes() + buffers->bytes();
    lap(options.phases, "gpu: upload");

    // A closed soup's points may take the sign of a coarse point's empty ball (setUpBake).
    const bool propagate = setup->soup.cycle;
    const BakePrograms& programs = setup->programs.front();
    BakePasses passes = makePasses(stats, options, setup->bvh.triangleCount);
    runCoarsePasses(passes, programs, sizes.coarseDims, propagate);
    runGridSlabs(passes, programs, *buffers, sizes, dims, progress);
    lap(options.phases, "gpu: passes");
    const std::vector<float> voxels = buffers->phi.download<float>();
    passes.readTimes();
    lap(options.phases, "gpu: readback");
    format::ColliderAsset asset = makeAsset(mesh, *grid, settings, setup->soup.method, voxels);
    lap(options.phases, "gpu: asset (world units, provenance, mass properties)");
    return asset;
}
} // namespace

Result<format::ColliderAsset> bakeGpu(const ImportedMesh& mesh, const BakeSettings& settings,
                                      gpu::Context& context, Progress* progress,
                                      const GpuBakeOptions& options, GpuBakeStats* stats) {
    context.makeCurrent();
    GpuBakeStats local;
    if (stats)
        *stats = {};
    return withGpuBakeErrors(mesh, [&] {
        return bakeChecked(mesh, settings, context, progress, options, stats ? *stats : local);
    });
}

} // namespace sluice::bake
