// Baking a collider asset on the GPU: CPU BVH, then coarse, fine and sign passes in GL compute.
//
// The soup is prepared as the CGAL reference prepares it (GpuSoup.h), then moved into
// grid-relative voxel coordinates, where grid point (i, j, k) is the float (i, j, k) and every
// coordinate is no larger than the grid.
//
// Passes (shaders/sdf_*.comp):
//   1. coarse distance: the nearest triangle of every 4th grid point along each axis;
//   2. coarse sign: their fast winding number (closed soups only);
//   3. fine distance, in z-slabs: exact distances, each invocation a block of 2 x 2 x 4 points
//      starting from the coarse triangles around it; a point inside a coarse point's empty ball
//      takes its sign (closed soups), blocks with other points go to a pending list;
//   4. after each slab, the fast winding number of the pending points, block by block, and the
//      exact one of the few too near the decision value.
// Every pass is split into dispatches of a bounded number of work groups; the CPU reads back two
// counters per slab and nothing else until the end.
#include "sluice/bake/GpuBaker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "Bvh.h"
#include "GpuSoup.h"
#include "sluice/bake/BakeShaders.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Gl.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/gpu/Program.h"

namespace sluice::bake {

namespace {

/// Slabs of the fine pass: between two slabs the CPU reads back how many points are pending and
/// reports progress. The first slab has about kFirstSlabPoints points; later ones are sized
/// from the measured rate to take about kSlabSeconds, up to kMaxSlabPoints (the lists' room),
/// so a slow device reports progress often and a fast one does not wait on many round trips.
/// The split does not change a bit of the result.
constexpr std::uint64_t kFirstSlabPoints = std::uint64_t(1) << 18;
constexpr std::uint64_t kMaxSlabPoints = std::uint64_t(1) << 22;
constexpr double kSlabSeconds = 0.1;
/// Solid angles one dispatch of the exact winding number computes at most (but one work group):
/// a few milliseconds on a GPU, so no dispatch runs long whatever the mesh.
constexpr std::uint64_t kExactSolidAnglesPerDispatch = std::uint64_t(1) << 26;

std::string mib(std::uint64_t bytes) {
    return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}

/// A buffer texture (samplerBuffer) over the whole of `buffer`, which must outlive it. RAII.
class BufferTexture {
public:
    BufferTexture(const gpu::Buffer& buffer, GLenum format) {
        glCreateTextures(GL_TEXTURE_BUFFER, 1, &m_id);
        glTextureBuffer(m_id, format, buffer.id());
    }
    BufferTexture(const BufferTexture&) = delete;
    BufferTexture& operator=(const BufferTexture&) = delete;
    ~BufferTexture() { glDeleteTextures(1, &m_id); }
    void bind(GLuint unit) const { glBindTextureUnit(unit, m_id); }

private:
    GLuint m_id = 0;
};

/// The programs of the bake, compiled from the embedded sources.
struct BakePrograms {
    gpu::Program coarse;     ///< sdf_coarse.comp
    gpu::Program distance;   ///< sdf_distance.comp
    gpu::Program coarseSign; ///< sdf_sign.comp with SDF_SIGN_COARSE
    gpu::Program sign;       ///< sdf_sign.comp over the pending list
    gpu::Program exactSign;  ///< sdf_sign.comp with SDF_SIGN_EXACT, over the verify list
};

Result<BakePrograms> compilePrograms() {
    auto compile = [](const char* name,
                      std::span<const gpu::ShaderDefine> defines = {}) -> Result<gpu::Program> {
        return gpu::Program::compute(name, shaders::shaderSource(name), defines);
    };
    Result<gpu::Program> coarse = compile("sdf_coarse.comp");
    if (!coarse)
        return coarse.error();
    Result<gpu::Program> distance = compile("sdf_distance.comp");
    if (!distance)
        return distance.error();
    const gpu::ShaderDefine coarseDefine[] = {{"SDF_SIGN_COARSE", "1"}};
    Result<gpu::Program> coarseSign = compile("sdf_sign.comp", coarseDefine);
    if (!coarseSign)
        return coarseSign.error();
    Result<gpu::Program> sign = compile("sdf_sign.comp");
    if (!sign)
        return sign.error();
    const gpu::ShaderDefine exactDefine[] = {{"SDF_SIGN_EXACT", "1"}};
    Result<gpu::Program> exactSign = compile("sdf_sign.comp", exactDefine);
    if (!exactSign)
        return exactSign.error();
    return BakePrograms{std::move(*coarse), std::move(*distance), std::move(*coarseSign),
                        std::move(*sign), std::move(*exactSign)};
}

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
    sizes.pending = sizeof(shared::PendingHeader) + slabBlocks * sizeof(glm::uvec2);
    sizes.verify = sizeof(shared::PendingHeader) +
                   slabBlocks * 4 * shared::kBakeBlockDepth * sizeof(std::uint32_t);
    sizes.triangles = 3 * triangles * sizeof(glm::vec4);
    // buildBvh makes fewer than two nodes per triangle, 2 texels each.
    sizes.nodes = 4 * triangles * sizeof(glm::uvec4);
    return sizes;
}

/// SizeOverflow or GpuOutOfMemory when the bake's buffers cannot exist on this GPU.
Result<void> checkSizes(const BakeSizes& sizes, const ImportedMesh& mesh, glm::uvec3 dims,
                        std::uint64_t triangles, gpu::Context& context,
                        const GpuBakeOptions& options) {
    const std::uint64_t maxBuffer =
        options.maxBufferBytes > 0 ? options.maxBufferBytes : context.info().maxSsboBytes;
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    const std::uint64_t maxTextureBytes =
        std::min(std::uint64_t(maxTexels) * sizeof(glm::vec4),
                 options.maxBufferBytes > 0 ? options.maxBufferBytes : ~std::uint64_t(0));
    const std::uint64_t largest = std::max({sizes.grid, sizes.coarse, sizes.pending, sizes.verify});
    if (largest > maxBuffer)
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": a grid of " + std::to_string(dims.x) + " x " +
                        std::to_string(dims.y) + " x " + std::to_string(dims.z) +
                        " points needs a " + mib(largest) +
                        " GPU buffer, over this GPU's largest storage buffer (" + mib(maxBuffer) +
                        "); use a coarser resolution or --backend cgal");
    if (triangles >= kBvhMaxTriangles || std::max(sizes.triangles, sizes.nodes) > maxTextureBytes)
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": " + std::to_string(triangles) +
                        " triangles need GPU buffers over this GPU's largest buffer texture (" +
                        mib(maxTextureBytes) + "); simplify the mesh or use --backend cgal");
    if (const auto& available = context.info().gpuMemoryAvailableBytes;
        available && sizes.total() > *available)
        return fail(ErrorCode::GpuOutOfMemory,
                    mesh.sourceFile + ": the bake needs " + mib(sizes.total()) +
                        " of GPU memory and " + mib(*available) +
                        " are free; use a coarser resolution or --backend cgal");
    return {};
}

Result<format::ColliderAsset> bakeChecked(const ImportedMesh& mesh, const BakeSettings& settings,
                                          gpu::Context& context, Progress* progress,
                                          const GpuBakeOptions& options, GpuBakeStats& stats) {
    Result<GridSpec> grid = gridFor(mesh.soup.bounds(), settings.grid);
    if (!grid)
        return grid.error();
    const auto cpuStart = std::chrono::steady_clock::now();
    Result<GpuSoup> soup = prepareGpuSoup(mesh.soup, mesh.diagnostics, settings.sign);
    if (!soup)
        return soup.error();

    // Grid-relative voxel coordinates: the float (i, j, k) is grid point (i, j, k) exactly.
    std::vector<BvhInputTriangle> input;
    input.reserve(soup->triangles.size());
    const double inverseVoxel = 1.0 / grid->voxelSize;
    auto toVoxels = [&](std::size_t v) { return (soup->points[v] - grid->origin) * inverseVoxel; };
    for (const auto& t : soup->triangles)
        input.push_back({toVoxels(t[0]), toVoxels(t[1]), toVoxels(t[2])});

    // Check sizes before building anything big.
    const glm::uvec3 dims = grid->dims;
    const BakeSizes sizes = bakeSizes(dims, input.size());
    if (Result<void> fits = checkSizes(sizes, mesh, dims, input.size(), context, options); !fits)
        return fits.error();

    const Bvh bvh = buildBvh(input);
    stats.triangles = bvh.triangleCount;
    stats.nodes = bvh.nodeCount;
    stats.depth = bvh.depth;
    stats.bvhSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - cpuStart).count();

    Result<BakePrograms> programs = compilePrograms();
    if (!programs)
        return programs.error();
    Result<gpu::Buffer> distanceNodes =
        gpu::Buffer::createFrom(bvh.distanceNodes, "bake BVH boxes");
    if (!distanceNodes)
        return distanceNodes.error();
    Result<gpu::Buffer> windingNodes =
        gpu::Buffer::createFrom(bvh.windingNodes, "bake BVH dipoles");
    if (!windingNodes)
        return windingNodes.error();
    Result<gpu::Buffer> triangles = gpu::Buffer::createFrom(bvh.triangles, "bake triangles");
    if (!triangles)
        return triangles.error();
    Result<gpu::Buffer> phi = gpu::Buffer::create(sizes.grid, "bake distances");
    if (!phi)
        return phi.error();
    Result<gpu::Buffer> coarse = gpu::Buffer::create(sizes.coarse, "bake coarse points");
    if (!coarse)
        return coarse.error();
    Result<gpu::Buffer> pending = gpu::Buffer::create(sizes.pending, "bake pending blocks");
    if (!pending)
        return pending.error();
    Result<gpu::Buffer> verify = gpu::Buffer::create(sizes.verify, "bake verify points");
    if (!verify)
        return verify.error();
    stats.gpuBytes = distanceNodes->size() + windingNodes->size() + triangles->size() +
                     phi->size() + coarse->size() + pending->size() + verify->size();
    const BufferTexture distanceTexture(*distanceNodes, GL_RGBA32UI);
    const BufferTexture windingTexture(*windingNodes, GL_RGBA32UI);
    const BufferTexture triangleTexture(*triangles, GL_RGBA32F);
    distanceTexture.bind(shared::kBakeDistanceNodesUnit);
    windingTexture.bind(shared::kBakeWindingNodesUnit);
    triangleTexture.bind(shared::kBakeTrianglesUnit);
    phi->bindStorage(shared::kBakeDistanceBinding);
    coarse->bindStorage(shared::kBakeCoarseBinding);
    pending->bindStorage(shared::kBakePendingBinding);
    verify->bindStorage(shared::kBakeVerifyBinding);

    // The winding number is an integer off a closed surface (a cycle), so a point's sign is that
    // of any point whose empty ball holds it; an open soup's is not, so every point is pending.
    const bool propagate = soup->cycle;
    BakePrograms& p = *programs;
    for (const gpu::Program* program :
         {&p.coarse, &p.distance, &p.coarseSign, &p.sign, &p.exactSign}) {
        program->set("dims", dims);
        program->set("nodeCount", bvh.nodeCount);
    }
    p.coarse.set("bvhDepth", bvh.depth);
    p.distance.set("propagate", std::uint32_t(propagate ? 1 : 0));
    for (const gpu::Program* program : {&p.coarseSign, &p.sign, &p.exactSign}) {
        program->set("triangleCount", bvh.triangleCount);
        program->set("beta", float(options.beta));
        program->set("verifyBand", float(options.verifyBand));
        program->set("parity", std::uint32_t(soup->method == format::SignMethod::Parity ? 1 : 0));
    }

    std::optional<gpu::GpuTimer> distanceTimer, signTimer;
    if (options.profile) {
        distanceTimer.emplace();
        signTimer.emplace();
    }
    auto timed = [&](std::optional<gpu::GpuTimer>& timer, auto&& pass) {
        if (timer)
            timer->begin();
        pass();
        if (timer)
            timer->end();
    };
    const std::uint64_t maxGroups = options.maxGroupsPerDispatch;
    // The exact winding number sums every triangle for each point, so its dispatches hold fewer
    // groups: about kExactSolidAnglesPerDispatch solid angles each, however large the mesh.
    const std::uint64_t exactGroups = std::clamp<std::uint64_t>(
        kExactSolidAnglesPerDispatch / (std::uint64_t(shared::kBakeLocalSize) * bvh.triangleCount),
        1, maxGroups);
    const std::uint32_t local = shared::kBakeLocalSize;

    // Coarse points: their nearest triangles, then (where the sign propagates) their signs.
    const glm::uvec3 groupSize(shared::kBakeGroupEdge, shared::kBakeGroupEdge,
                               shared::kBakeGroupDepth); // [points]
    const glm::uvec3 coarseDims = sizes.coarseDims;
    const std::uint32_t coarseCount = coarseDims.x * coarseDims.y * coarseDims.z;
    timed(distanceTimer, [&] {
        stats.dispatches +=
            p.coarse.dispatchChunked(gpu::groupCount(coarseDims, groupSize), maxGroups);
    });
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    if (propagate) {
        p.coarseSign.set("itemCount", coarseCount);
        timed(signTimer, [&] {
            stats.dispatches += p.coarseSign.dispatchChunked(
                glm::uvec3(gpu::groupCount(coarseCount, local), 1, 1), maxGroups);
        });
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }

    // The grid in z-slabs of work groups: the fine distance pass, then the sign of the points
    // it left pending. Between slabs the CPU reads the pending count and reports progress.
    const std::uint32_t groupDepth = shared::kBakeGroupDepth;
    const glm::uvec3 groups = gpu::groupCount(dims, groupSize);
    const std::uint64_t slice = std::uint64_t(dims.x) * dims.y;
    std::uint32_t slabGroups = sizes.slabGroups;
    for (std::uint32_t z0 = 0, z1 = 0; z0 < groups.z; z0 = z1) {
        const auto slabStart = std::chrono::steady_clock::now();
        z1 = std::min(groups.z, z0 + slabGroups);
        const shared::PendingHeader empty{};
        pending->upload(&empty, sizeof(empty));
        verify->upload(&empty, sizeof(empty));
        p.distance.set("groupBegin", z0);
        timed(distanceTimer, [&] {
            stats.dispatches +=
                p.distance.dispatchChunked(glm::uvec3(groups.x, groups.y, z1 - z0), maxGroups);
        });
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        shared::PendingHeader header{};
        pending->download(&header, sizeof(header));
        if (header.count > 0) {
            p.sign.set("itemCount", header.count);
            timed(signTimer, [&] {
                stats.dispatches += p.sign.dispatchChunked(
                    glm::uvec3(gpu::groupCount(header.count, local), 1, 1), maxGroups);
            });
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
            // Points whose fast winding number was too near the decision: the exact sum.
            shared::PendingHeader verified{};
            verify->download(&verified, sizeof(verified));
            if (verified.count > 0) {
                p.exactSign.set("itemCount", verified.count);
                timed(signTimer, [&] {
                    stats.dispatches += p.exactSign.dispatchChunked(
                        glm::uvec3(gpu::groupCount(verified.count, local), 1, 1), exactGroups);
                });
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            }
            stats.verifiedPoints += verified.count;
        }
        stats.pendingPoints += header.points;
        if (progress) {
            const std::uint32_t k0 = z0 * groupDepth, k1 = std::min(dims.z, z1 * groupDepth);
            progress->add(std::uint64_t(k1 - k0) * slice);
        }
        // The next slab: about kSlabSeconds at this slab's rate, growing at most 4 times.
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - slabStart).count();
        const double scale = std::min(4.0, kSlabSeconds / std::max(seconds, 1e-6));
        slabGroups = std::uint32_t(
            std::clamp<double>(std::floor((z1 - z0) * scale), 1.0, double(sizes.maxSlabGroups)));
    }
    const std::vector<float> voxels = phi->download<float>();
    if (distanceTimer) {
        (void)distanceTimer->elapsedNs();
        stats.distanceNs = distanceTimer->totalNs();
        if (signTimer->completed() > 0 || signTimer->pending() > 0) {
            (void)signTimer->elapsedNs();
            stats.signNs = signTimer->totalNs();
        }
    }

    format::ColliderAsset asset;
    asset.meta = bakeProvenance(mesh, *grid, settings, "gpu", soup->method);
    // Voxels to world units in double, so the only float rounding is the GPU's and the last one.
    asset.distances.resize(voxels.size());
    std::transform(voxels.begin(), voxels.end(), asset.distances.begin(),
                   [&](float v) { return float(double(v) * grid->voxelSize); });
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
    // CGAL (orientation) reports broken preconditions and allocation failures by throwing.
    try {
        Result<format::ColliderAsset> asset =
            bakeChecked(mesh, settings, context, progress, options, stats ? *stats : local);
        return asset;
    } catch (const std::bad_alloc&) {
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": out of memory while baking; use a coarser grid");
    } catch (const std::exception& e) {
        return fail(ErrorCode::Unsupported, mesh.sourceFile +
                                                ": preparing this mesh for the GPU bake failed (" +
                                                e.what() + ")");
    }
}

} // namespace sluice::bake
