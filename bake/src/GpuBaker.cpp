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

Result<BakePrograms> compilePrograms(gpu::ProgramCache* cache) {
    auto compile = [cache](const char* name,
                           std::span<const gpu::ShaderDefine> defines = {}) -> Result<gpu::Program> {
        return cache ? cache->compute(name, shaders::shaderSource(name), defines)
                     : gpu::Program::compute(name, shaders::shaderSource(name), defines);
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

/// The soup's triangles in grid-relative voxel coordinates: the float (i, j, k) is grid point
/// (i, j, k) exactly.
std::vector<BvhInputTriangle> voxelTriangles(const GpuSoup& soup, const GridSpec& grid) {
    std::vector<BvhInputTriangle> input;
    input.reserve(soup.triangles.size());
    const double inverseVoxel = 1.0 / grid.voxelSize;
    auto toVoxels = [&](std::size_t v) { return (soup.points[v] - grid.origin) * inverseVoxel; };
    for (const auto& t : soup.triangles)
        input.push_back({toVoxels(t[0]), toVoxels(t[1]), toVoxels(t[2])});
    return input;
}

/// The bake's GPU buffers.
struct BakeBuffers {
    gpu::Buffer distanceNodes; ///< BVH boxes and links (texels)
    gpu::Buffer windingNodes;  ///< BVH dipoles and links (texels)
    gpu::Buffer triangles;     ///< triangle corners in leaf order (texels)
    gpu::Buffer phi;           ///< distance per grid point [voxels]
    gpu::Buffer coarse;        ///< CoarsePoint per coarse point
    gpu::Buffer pending;       ///< PendingHeader, then the blocks of a slab still without a sign
    gpu::Buffer verify;        ///< PendingHeader, then the points of a slab for the exact sum

    std::uint64_t bytes() const {
        return distanceNodes.size() + windingNodes.size() + triangles.size() + phi.size() +
               coarse.size() + pending.size() + verify.size();
    }
};

Result<BakeBuffers> createBuffers(const Bvh& bvh, const BakeSizes& sizes) {
    BakeBuffers b;
    struct Upload {
        gpu::Buffer* buffer;
        Result<gpu::Buffer> created;
    };
    Upload uploads[] = {
        {&b.distanceNodes, gpu::Buffer::createFrom(bvh.distanceNodes, "bake BVH boxes")},
        {&b.windingNodes, gpu::Buffer::createFrom(bvh.windingNodes, "bake BVH dipoles")},
        {&b.triangles, gpu::Buffer::createFrom(bvh.triangles, "bake triangles")},
    };
    for (Upload& u : uploads) {
        if (!u.created)
            return u.created.error();
        *u.buffer = std::move(*u.created);
    }
    struct Alloc {
        gpu::Buffer* buffer;
        std::uint64_t bytes;
        const char* label;
    };
    const Alloc allocs[] = {
        {&b.phi, sizes.grid, "bake distances"},
        {&b.coarse, sizes.coarse, "bake coarse points"},
        {&b.pending, sizes.pending, "bake pending blocks"},
        {&b.verify, sizes.verify, "bake verify points"},
    };
    for (const Alloc& a : allocs) {
        Result<gpu::Buffer> buffer = gpu::Buffer::create(a.bytes, a.label);
        if (!buffer)
            return buffer.error();
        *a.buffer = std::move(*buffer);
    }
    return b;
}

/// The BVH and triangles as buffer textures on their units, and the storage buffers on their
/// bindings, for the passes of one bake. `buffers` must outlive it.
struct BoundBuffers {
    explicit BoundBuffers(const BakeBuffers& buffers)
        : distanceTexture(buffers.distanceNodes, GL_RGBA32UI),
          windingTexture(buffers.windingNodes, GL_RGBA32UI),
          triangleTexture(buffers.triangles, GL_RGBA32F) {
        distanceTexture.bind(shared::kBakeDistanceNodesUnit);
        windingTexture.bind(shared::kBakeWindingNodesUnit);
        triangleTexture.bind(shared::kBakeTrianglesUnit);
        buffers.phi.bindStorage(shared::kBakeDistanceBinding);
        buffers.coarse.bindStorage(shared::kBakeCoarseBinding);
        buffers.pending.bindStorage(shared::kBakePendingBinding);
        buffers.verify.bindStorage(shared::kBakeVerifyBinding);
    }
    BufferTexture distanceTexture, windingTexture, triangleTexture;
};

/// The uniforms that stay the same for the whole bake. `propagate`: the fine pass may take the
/// sign of a coarse point whose empty ball holds a grid point.
void setBakeUniforms(const BakePrograms& p, const Bvh& bvh, glm::uvec3 dims, bool propagate,
                     format::SignMethod method, const GpuBakeOptions& options) {
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
        program->set("parity", std::uint32_t(method == format::SignMethod::Parity ? 1 : 0));
    }
}

/// What the passes of one bake share: their programs, the dispatch limits, the timers (profile
/// only) and the statistics they add to.
struct BakePasses {
    const BakePrograms& programs;
    GpuBakeStats& stats;
    std::uint64_t maxGroups = 0;   ///< work groups per dispatch
    std::uint64_t exactGroups = 0; ///< work groups per dispatch of the exact winding number
    std::optional<gpu::GpuTimer> distanceTimer, signTimer;

    /// A distance pass over `groups` work groups, timed with the distance passes.
    void distance(const gpu::Program& program, glm::uvec3 groups) {
        timed(distanceTimer,
              [&] { stats.dispatches += program.dispatchChunked(groups, maxGroups); });
    }
    /// A sign pass over `items` list entries, `groupsPerDispatch` work groups per dispatch,
    /// timed with the sign passes.
    void sign(const gpu::Program& program, std::uint32_t items, std::uint64_t groupsPerDispatch) {
        program.set("itemCount", items);
        const std::uint32_t local = shared::kBakeLocalSize;
        const glm::uvec3 groups(gpu::groupCount(items, local), 1, 1);
        timed(signTimer,
              [&] { stats.dispatches += program.dispatchChunked(groups, groupsPerDispatch); });
    }

private:
    template <class Pass> static void timed(std::optional<gpu::GpuTimer>& timer, Pass&& pass) {
        if (timer)
            timer->begin();
        pass();
        if (timer)
            timer->end();
    }
};

BakePasses makePasses(const BakePrograms& programs, GpuBakeStats& stats,
                      const GpuBakeOptions& options, std::uint32_t triangleCount) {
    BakePasses passes{programs, stats};
    passes.maxGroups = options.maxGroupsPerDispatch;
    // The exact winding number sums every triangle for each point, so its dispatches hold fewer
    // groups: about kExactSolidAnglesPerDispatch solid angles each, however large the mesh.
    passes.exactGroups = std::clamp<std::uint64_t>(
        kExactSolidAnglesPerDispatch / (std::uint64_t(shared::kBakeLocalSize) * triangleCount), 1,
        passes.maxGroups);
    if (options.profile) {
        passes.distanceTimer.emplace();
        passes.signTimer.emplace();
    }
    return passes;
}

/// Grid points per work group of the distance passes.
const glm::uvec3 kGroupPoints(shared::kBakeGroupEdge, shared::kBakeGroupEdge,
                              shared::kBakeGroupDepth);

/// Passes 1 and 2: the coarse points' nearest triangles, then (where the sign propagates) their
/// signs.
void runCoarsePasses(BakePasses& passes, glm::uvec3 coarseDims, bool propagate) {
    passes.distance(passes.programs.coarse, gpu::groupCount(coarseDims, kGroupPoints));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    if (propagate) {
        passes.sign(passes.programs.coarseSign, coarseDims.x * coarseDims.y * coarseDims.z,
                    passes.maxGroups);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
}

/// Pass 4 for the slab just computed: the fast winding number of its pending blocks, then the
/// exact one of the points too near the decision. Reads back the two list headers.
void signPendingPoints(BakePasses& passes, const BakeBuffers& buffers) {
    shared::PendingHeader header{};
    buffers.pending.download(&header, sizeof(header));
    if (header.count > 0) {
        passes.sign(passes.programs.sign, header.count, passes.maxGroups);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        shared::PendingHeader verified{};
        buffers.verify.download(&verified, sizeof(verified));
        if (verified.count > 0) {
            passes.sign(passes.programs.exactSign, verified.count, passes.exactGroups);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        }
        passes.stats.verifiedPoints += verified.count;
    }
    passes.stats.pendingPoints += header.points;
}

/// Work-group layers of the slab after one of `done` layers that took `seconds`: about
/// kSlabSeconds at its rate, growing at most 4 times, within [1, maxSlabGroups].
std::uint32_t nextSlabGroups(std::uint32_t done, double seconds, std::uint32_t maxSlabGroups) {
    const double scale = std::min(4.0, kSlabSeconds / std::max(seconds, 1e-6));
    return std::uint32_t(std::clamp<double>(std::floor(done * scale), 1.0, double(maxSlabGroups)));
}

/// Passes 3 and 4 over the grid in z-slabs of work groups: the fine distance pass, then the
/// sign of the points it left pending. Between slabs the CPU reads the pending count and
/// reports progress.
void runSlabs(BakePasses& passes, BakeBuffers& buffers, const BakeSizes& sizes, glm::uvec3 dims,
              Progress* progress) {
    const glm::uvec3 groups = gpu::groupCount(dims, kGroupPoints);
    const std::uint64_t slice = std::uint64_t(dims.x) * dims.y;
    std::uint32_t slabGroups = sizes.slabGroups;
    for (std::uint32_t z0 = 0, z1 = 0; z0 < groups.z; z0 = z1) {
        const auto slabStart = std::chrono::steady_clock::now();
        z1 = std::min(groups.z, z0 + slabGroups);
        const shared::PendingHeader empty{};
        buffers.pending.upload(&empty, sizeof(empty));
        buffers.verify.upload(&empty, sizeof(empty));
        passes.programs.distance.set("groupBegin", z0);
        passes.distance(passes.programs.distance, glm::uvec3(groups.x, groups.y, z1 - z0));
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        signPendingPoints(passes, buffers);
        if (progress) {
            const std::uint32_t groupDepth = shared::kBakeGroupDepth;
            const std::uint32_t k0 = z0 * groupDepth, k1 = std::min(dims.z, z1 * groupDepth);
            progress->add(std::uint64_t(k1 - k0) * slice);
        }
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - slabStart).count();
        slabGroups = nextSlabGroups(z1 - z0, seconds, sizes.maxSlabGroups);
    }
}

/// The GPU time of the passes into the statistics (profile only; waits for the queries).
void readPassTimes(BakePasses& passes) {
    if (!passes.distanceTimer)
        return;
    (void)passes.distanceTimer->elapsedNs();
    passes.stats.distanceNs = passes.distanceTimer->totalNs();
    if (passes.signTimer->completed() > 0 || passes.signTimer->pending() > 0) {
        (void)passes.signTimer->elapsedNs();
        passes.stats.signNs = passes.signTimer->totalNs();
    }
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
    const auto cpuStart = std::chrono::steady_clock::now();
    const auto lap = [&](std::string_view name) { bake::lap(options.phases, name); };
    Result<GpuSoup> soup = prepareGpuSoup(mesh.soup, mesh.diagnostics, settings.sign);
    if (!soup)
        return soup.error();
    lap("gpu: prepare the soup");
    const std::vector<BvhInputTriangle> input = voxelTriangles(*soup, *grid);

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
    lap("gpu: BVH build");

    Result<BakePrograms> programs = compilePrograms(options.programCache);
    if (!programs)
        return programs.error();
    lap("gpu: compile and link programs");
    Result<BakeBuffers> buffers = createBuffers(bvh, sizes);
    if (!buffers)
        return buffers.error();
    stats.gpuBytes = buffers->bytes();
    const BoundBuffers bound(*buffers);
    lap("gpu: upload");

    // The winding number is an integer off a closed surface (a cycle), so a point's sign is that
    // of any point whose empty ball holds it; an open soup's is not, so every point is pending.
    const bool propagate = soup->cycle;
    setBakeUniforms(*programs, bvh, dims, propagate, soup->method, options);
    BakePasses passes = makePasses(*programs, stats, options, bvh.triangleCount);
    runCoarsePasses(passes, sizes.coarseDims, propagate);
    runSlabs(passes, *buffers, sizes, dims, progress);
    lap("gpu: passes");
    const std::vector<float> voxels = buffers->phi.download<float>();
    readPassTimes(passes);
    lap("gpu: readback");
    format::ColliderAsset asset = makeAsset(mesh, *grid, settings, soup->method, voxels);
    lap("gpu: asset (world units, provenance, mass properties)");
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
