// Sparse bakes: band bricks found by culling, exact distances only there, NanoVDB out. What
// both backends share (bakeSparseCgal in cgal/CgalSparseBaker.cpp, bakeSparseGpu in
// gpu/GpuSparseBaker.cpp); the exact values are theirs.
//
// The steps of a sparse bake:
//   1. sparseGridFor: the domain, as a dense bake's grid with padding >= band + 1 voxels.
//   2. planSparse: blocks of power-of-two edge, from one covering the domain down to 8^3 bricks.
//      A block whose centre is farther from the surface than its half-diagonal plus the band
//      holds no band voxel (triangle inequality) and keeps one sign: it is uniform. The rest
//      split; what is left at edge 8 are the band bricks.
//   3. The backend's exact signed distances at every brick voxel, in batches, and one signed
//      sample at each uniform block's centre.
//   4. SparseGridBuilder: OpenVDB leaves from the bricks, inside blocks filled as inactive
//      tiles of -band (OpenVDB picks the largest tiles that fit), then openToNanoVDB.
#include "sluice/bake/sparse/SparseBaker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "interop/NanoVdbHeaders.h"
#include "sluice/bake/jobs/PhaseLog.h"
#include "sluice/format/asset/NanoVdbCheck.h"
#include "sluice/format/scene/SimulationLimits.h"
#include "sluice/format/scene/SolverReach.h"
#include "sluice/format/support/NumberText.h"
#include "sparse/SparseBricks.h"

namespace sluice::bake {

namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;
static_assert(FloatLeaf::DIM == kBrickSize, "a brick is one OpenVDB / NanoVDB leaf");

/// A NanoVDB buffer type (what GridHandle and openToNanoVDB need of one) over GridBytes, so the
/// converted grid is moved into the asset instead of copied: one grid in memory, not two.
struct GridBytesBuffer {
    std::shared_ptr<format::GridBytes> bytes = std::make_shared<format::GridBytes>();
    static GridBytesBuffer create(std::uint64_t size, const GridBytesBuffer* = nullptr) {
        GridBytesBuffer buffer;
        buffer.bytes->resize(size);
        return buffer;
    }
    std::uint8_t* data() { return reinterpret_cast<std::uint8_t*>(bytes->data()); }
    const std::uint8_t* data() const {
        return reinterpret_cast<const std::uint8_t*>(bytes->data());
    }
    std::uint64_t size() const { return bytes->size(); }
    bool empty() const { return bytes->empty(); }
    void clear() { bytes = std::make_shared<format::GridBytes>(); }
};

/// "0.02": a length or a count with a few significant digits, for messages.

} // namespace

double sparsePadding(double padding, double band) {
    return std::max(padding, std::ceil(band) + 1.0);
}

Result<double> bandForVoxel(double voxel, double spacing, double kernelRadius) {
    if (!std::isfinite(spacing) || !(spacing > 0.0))
        return fail(ErrorCode::InvalidArgument,
                    "--for-spacing must be a particle spacing > 0, got " + std::to_string(spacing));
    // In single precision, as a scene holds them, so the range's ends are the scene reader's.
    const double h =
        double(float(kernelRadius > 0.0 ? kernelRadius : format::kDefaultKernelSpacings * spacing));
    const format::ParamRange range =
        format::simulationParamRange("kernelRadius", float(spacing), float(h));
    if (const std::string problem = format::rangeProblem(h, format::significant(h, 3), range);
        !problem.empty())
        return fail(ErrorCode::InvalidArgument, "--for-kernel-radius: " + problem);
    const double reach = format::colliderReach(spacing, h, true);
    const double band = std::max(1.0, std::ceil(format::requiredBandVoxels(reach, voxel)));
    if (band > 64.0)
        return fail(ErrorCode::InvalidArgument,
                    "a particle spacing of " + format::significant(spacing, 3) +
                        " needs a band of " + format::significant(band, 3) + " voxels of " +
                        format::significant(voxel, 3) +
                        ", over the 64 a sparse bake allows; bake with a coarser --resolution or "
                        "--voxel-size, or bake dense");
    return band;
}

Result<double> bandForSpacing(const Box& bounds, const GridOptions& options, double spacing,
                              double kernelRadius) {
    GridOptions probe = options;
    probe.maxPoints = kMaxSparseGridPoints;
    auto grid = gridFor(bounds, probe); // the voxel size; the padding does not change it
    if (!grid)
        return grid.error();
    return bandForVoxel(grid->voxelSize, spacing, kernelRadius);
}

Result<GridSpec> sparseGridFor(const Box& bounds, GridOptions options, double band) {
    if (!std::isfinite(band) || band < 1.0 || band > 64.0)
        return fail(ErrorCode::InvalidArgument,
                    "band must be between 1 and 64 voxels, got " + std::to_string(band));
    options.padding = sparsePadding(options.padding, band);
    options.maxPoints = kMaxSparseGridPoints;
    return gridFor(bounds, options);
}

SparsePlan planSparse(const GridSpec& grid, double band, const DistanceQuery& unsignedDistance) {
    SparsePlan plan;
    const std::uint32_t longest = std::max(grid.dims.x, std::max(grid.dims.y, grid.dims.z));
    std::int32_t edge = std::int32_t(kBrickSize);
    while (std::uint32_t(edge) < longest)
        edge *= 2;
    const double h = grid.voxelSize;
    std::vector<glm::ivec3> level{glm::ivec3(0)};
    std::vector<glm::ivec3> next;
    std::vector<glm::dvec3> centres;
    std::vector<double> distance;
    while (!level.empty()) {
        const double halfEdge = 0.5 * double(edge - 1); // [voxels] centre to the last voxel
        centres.resize(level.size());
        for (std::size_t n = 0; n < level.size(); ++n)
            centres[n] = grid.origin + (glm::dvec3(level[n]) + halfEdge) * h;
        distance.resize(level.size());
        unsignedDistance(centres, distance);
        plan.distanceQueries += level.size();
        // Every voxel of the block lies within sqrt(3) * halfEdge voxels of its centre.
        const double reach = (std::sqrt(3.0) * halfEdge + band) * h * (1.0 + 1e-9);
        next.clear();
        for (std::size_t n = 0; n < level.size(); ++n) {
            if (distance[n] > reach) {
                plan.blocks.push_back(level[n]);
                plan.blockEdge.push_back(edge);
            } else if (edge == std::int32_t(kBrickSize)) {
                plan.bricks.push_back(level[n]);
            } else {
                const std::int32_t half = edge / 2;
                for (int c = 0; c < 8; ++c) {
                    const glm::ivec3 child =
                        level[n] + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1) * half;
                    if (insideDomain(child, grid.dims))
                        next.push_back(child);
                }
            }
        }
        level.swap(next);
        edge /= 2;
    }
    return plan;
}

struct SparseGridBuilder::Impl {
    GridSpec grid;
    float background = 0.0f;
    openvdb::FloatGrid::Ptr vdb;
};

SparseGridBuilder::SparseGridBuilder(const GridSpec& grid, double band)
    : m_impl(std::make_unique<Impl>()) {
    initOpenVdb();
    m_impl->grid = grid;
    m_impl->background = float(band * grid.voxelSize);
    m_impl->vdb = openvdb::FloatGrid::create(m_impl->background);
}

SparseGridBuilder::~SparseGridBuilder() = default;

void SparseGridBuilder::addBricks(std::span<const glm::ivec3> corners,
                                  std::span<const float> values) {
    SLUICE_ASSERT(values.size() == corners.size() * kBrickVoxels, "addBricks: value count");
    const float bg = m_impl->background;
    const glm::uvec3 dims = m_impl->grid.dims;
    std::vector<std::unique_ptr<FloatLeaf>> leaves(corners.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, corners.size(), 16), [&](const auto& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            const glm::ivec3 lo = corners[b];
            auto leaf = std::make_unique<FloatLeaf>(openvdb::Coord(lo.x, lo.y, lo.z), bg, false);
            for (std::uint32_t v = 0; v < kBrickVoxels; ++v) {
                const glm::ivec3 p = lo + brickVoxel(v);
                if (!insideDomain(p, dims))
                    continue;
                const float d = values[b * kBrickVoxels + v];
                const openvdb::Index offset =
                    FloatLeaf::coordToOffset(openvdb::Coord(p.x, p.y, p.z));
                if (std::abs(d) < bg)
                    leaf->setValueOn(offset, d);
                else
                    leaf->setValueOff(offset, d < 0.0f ? -bg : bg);
            }
            leaves[b] = std::move(leaf);
        }
    });
    for (auto& leaf : leaves)
        m_impl->vdb->tree().addLeaf(leaf.release());
}

void SparseGridBuilder::fillInside(const glm::ivec3& lo, std::int32_t edge) {
    const glm::ivec3 hi = lo + edge - 1;
    m_impl->vdb->tree().fill(
        openvdb::CoordBBox(openvdb::Coord(lo.x, lo.y, lo.z), openvdb::Coord(hi.x, hi.y, hi.z)),
        -m_impl->background, false);
}

Result<format::GridBytes> SparseGridBuilder::finish() {
    openvdb::FloatGrid::Ptr vdb = std::move(m_impl->vdb);
    const GridSpec& grid = m_impl->grid;
    auto transform = openvdb::math::Transform::createLinearTransform(grid.voxelSize);
    transform->postTranslate(openvdb::Vec3d(grid.origin.x, grid.origin.y, grid.origin.z));
    vdb->setTransform(transform);
    vdb->setGridClass(openvdb::GRID_LEVEL_SET);
    vdb->setName("sdf");
    try {
        auto handle = nanovdb::openToNanoVDB<GridBytesBuffer>(*vdb);
        vdb.reset();
        if (handle.size() > format::kMaxNanoVdbBytes)
            return fail(ErrorCode::SizeOverflow,
                        "the sparse grid needs " + std::to_string(handle.size()) +
                            " bytes, over the limit of " +
                            std::to_string(format::kMaxNanoVdbBytes) +
                            "; use a coarser resolution or a narrower band");
        const std::shared_ptr<format::GridBytes> bytes = handle.buffer().bytes;
        return std::move(*bytes);
    } catch (const std::bad_alloc&) {
        return fail(ErrorCode::SizeOverflow, "out of memory while building the sparse grid");
    } catch (const std::exception& e) {
        return fail(ErrorCode::Unsupported,
                    std::string("OpenVDB/NanoVDB failed to build the sparse grid: ") + e.what());
    }
}

format::ColliderMeta sparseProvenance(const ImportedMesh& mesh, const GridSpec& grid,
                                      const BakeSettings& settings, const char* backend,
                                      format::SignMethod method, double band) {
    format::ColliderMeta meta = bakeProvenance(mesh, grid, settings, backend, method);
    meta.storage = format::Storage::F32;
    meta.layout = format::Layout::Sparse;
    meta.bandWidth = band;
    meta.bake.padding = sparsePadding(settings.grid.padding, band);
    return meta;
}

Result<format::ColliderAsset> finishSparseAsset(SparseGridBuilder& builder, const SparsePlan& plan,
                                                std::span<const double> blockPhi,
                                                format::ColliderMeta meta, SparseBakeStats& stats) {
    SLUICE_ASSERT(blockPhi.size() == plan.blocks.size(), "finishSparseAsset: one phi per block");
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t n = 0; n < plan.blocks.size(); ++n)
        if (blockPhi[n] < 0.0)
            builder.fillInside(plan.blocks[n], plan.blockEdge[n]);
    Result<format::GridBytes> bytes = builder.finish();
    if (!bytes)
        return bytes.error();
    stats.buildSeconds += secondsSince(start);
    format::ColliderAsset asset;
    asset.meta = std::move(meta);
    asset.grid = std::move(*bytes);
    auto tree = format::checkNanoVdbGrid(asset.grid, asset.meta.sourceFile);
    SLUICE_ASSERT(tree.ok(), "a sparse bake wrote a grid its own check rejects");
    stats.activeVoxels = tree->activeVoxels;
    stats.gridBytes = tree->bytes;
    return asset;
}

std::vector<glm::dvec3> blockCentres(const GridSpec& grid, const SparsePlan& plan) {
    std::vector<glm::dvec3> centres(plan.blocks.size());
    for (std::size_t n = 0; n < plan.blocks.size(); ++n)
        centres[n] =
            grid.origin +
            (glm::dvec3(plan.blocks[n]) + 0.5 * double(plan.blockEdge[n] - 1)) * grid.voxelSize;
    return centres;
}

void recordPlan(const SparsePlan& plan, double seconds, SparseBakeStats& stats) {
    stats.planSeconds = seconds;
    stats.bricks = plan.bricks.size();
    stats.uniformBlocks = plan.blocks.size();
    stats.distanceQueries = plan.distanceQueries;
}

} // namespace sluice::bake
