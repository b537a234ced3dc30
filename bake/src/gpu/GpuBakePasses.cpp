// The passes and buffers the dense and sparse GPU bakes share (GpuBakePasses.h).
#include "gpu/GpuBakePasses.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "sluice/bake/BakeShaders.h"

namespace sluice::bake {

namespace {

/// Seconds a slab of the fine pass should take: a slow device reports progress often and a fast
/// one does not wait on many round trips.
constexpr double kSlabSeconds = 0.1;
/// Solid angles one dispatch of the exact winding number computes at most (but one work group):
/// a few milliseconds on a GPU, so no dispatch runs long whatever the mesh.
constexpr std::uint64_t kExactSolidAnglesPerDispatch = std::uint64_t(1) << 26;

/// Work-group layers of the slab after one of `done` layers that took `seconds`: about
/// kSlabSeconds at its rate, growing at most 4 times, within [1, maxLayers].
std::uint32_t nextSlabLayers(std::uint32_t done, double seconds, std::uint32_t maxLayers) {
    const double scale = std::min(4.0, kSlabSeconds / std::max(seconds, 1e-6));
    return std::uint32_t(std::clamp<double>(std::floor(done * scale), 1.0, double(maxLayers)));
}

template <class Pass> void timed(std::optional<gpu::GpuTimer>& timer, Pass&& pass) {
    if (timer)
        timer->begin();
    pass();
    if (timer)
        timer->end();
}

/// The fast winding number of the slab's pending blocks, then the exact one of the points too
/// near the decision. Reads back the two list headers.
void signPendingPoints(BakePasses& passes, const BakePrograms& programs, const SignLists& lists) {
    shared::PendingHeader header{};
    lists.pending.download(&header, sizeof(header));
    if (header.count > 0) {
        passes.sign(programs.sign, header.count, passes.maxGroups);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        shared::PendingHeader verified{};
        lists.verify.download(&verified, sizeof(verified));
        if (verified.count > 0) {
            passes.sign(programs.exactSign, verified.count, passes.exactGroups);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        }
        passes.stats.verifiedPoints += verified.count;
    }
    passes.stats.pendingPoints += header.points;
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

/// The soup prepared for the GPU (GpuSoup.h) and its triangles in grid-relative voxels.
struct VoxelSoup {
    GpuSoup soup;
    std::vector<BvhInputTriangle> triangles;
};

/// Prepares the soup and lays it over the grid; laps "gpu: prepare the soup". Errors of
/// prepareGpuSoup.
Result<VoxelSoup> prepareVoxelSoup(const ImportedMesh& mesh, const GridSpec& grid, SignMode sign,
                                   PhaseLog* phases) {
    Result<GpuSoup> soup = prepareGpuSoup(mesh.soup, mesh.diagnostics, sign);
    if (!soup)
        return soup.error();
    lap(phases, "gpu: prepare the soup");
    std::vector<BvhInputTriangle> triangles = voxelTriangles(*soup, grid);
    return VoxelSoup{std::move(*soup), std::move(triangles)};
}

/// Builds the BVH over `triangles` and records its figures in `stats` (bvhSeconds from
/// `start`, the soup's preparation included); laps "gpu: BVH build".
Bvh buildBakeBvh(std::span<const BvhInputTriangle> triangles, GpuBakeStats& stats,
                 std::chrono::steady_clock::time_point start, PhaseLog* phases) {
    Bvh bvh = buildBvh(triangles);
    stats.triangles = bvh.triangleCount;
    stats.nodes = bvh.nodeCount;
    stats.depth = bvh.depth;
    stats.bvhSeconds = secondsSince(start);
    lap(phases, "gpu: BVH build");
    return bvh;
}

/// The BVH and its triangles as buffer textures bound to their units (shared/SdfBake.h).
Result<GpuBvh> uploadBvh(const Bvh& bvh) {
    GpuBvh out;
    struct Upload {
        gpu::Buffer* buffer;
        Result<gpu::Buffer> created;
    };
    Upload uploads[] = {
        {&out.distanceNodes, gpu::Buffer::createFrom(bvh.distanceNodes, "bake BVH boxes")},
        {&out.windingNodes, gpu::Buffer::createFrom(bvh.windingNodes, "bake BVH dipoles")},
        {&out.triangles, gpu::Buffer::createFrom(bvh.triangles, "bake triangles")},
    };
    for (Upload& u : uploads) {
        if (!u.created)
            return u.created.error();
        *u.buffer = std::move(*u.created);
    }
    struct View {
        const gpu::Buffer& buffer;
        gpu::TexelFormat format;
        GLuint unit;
        const char* label;
    };
    const View views[] = {
        {out.distanceNodes, gpu::TexelFormat::RGBA32UI, shared::kBakeDistanceNodesUnit,
         "bake BVH boxes"},
        {out.windingNodes, gpu::TexelFormat::RGBA32UI, shared::kBakeWindingNodesUnit,
         "bake BVH dipoles"},
        {out.triangles, gpu::TexelFormat::RGBA32F, shared::kBakeTrianglesUnit, "bake triangles"},
    };
    for (const View& v : views) {
        auto texture = gpu::BufferTexture::create(v.buffer, v.format, v.label);
        if (!texture)
            return texture.error();
        texture->bindTexture(v.unit);
        out.textures.push_back(std::move(*texture));
    }
    return out;
}

/// The programs of the bake for one layout, compiled from the embedded sources.
Result<BakePrograms> compilePrograms(gpu::ProgramCache* cache, BakeLayout layout) {
    std::vector<gpu::ShaderDefine> base;
    if (layout == BakeLayout::Sparse)
        base.push_back({"SDF_SPARSE", "1"});
    if (layout == BakeLayout::Points)
        base.push_back({"SDF_POINTS", "1"});
    auto compile = [&](const char* name, const char* variant = nullptr) -> Result<gpu::Program> {
        std::vector<gpu::ShaderDefine> defines = base;
        if (variant)
            defines.push_back({variant, "1"});
        return cache ? cache->compute(name, shaders::shaderSource(name), defines)
                     : gpu::Program::compute(name, shaders::shaderSource(name), defines);
    };
    BakePrograms p;
    struct Job {
        gpu::Program* program;
        const char* name;
        const char* variant;
    };
    std::vector<Job> jobs = {{&p.coarse, "sdf_coarse.comp", nullptr},
                             {&p.coarseSign, "sdf_sign.comp", "SDF_SIGN_COARSE"}};
    if (layout != BakeLayout::Points) {
        jobs.push_back({&p.distance, "sdf_distance.comp", nullptr});
        jobs.push_back({&p.sign, "sdf_sign.comp", nullptr});
        jobs.push_back({&p.exactSign, "sdf_sign.comp", "SDF_SIGN_EXACT"});
    }
    for (const Job& job : jobs) {
        Result<gpu::Program> program = compile(job.name, job.variant);
        if (!program)
            return program.error();
        *job.program = std::move(*program);
    }
    return p;
}

/// The uniforms that stay the same for the whole bake. `propagate`: the fine pass may take the
/// sign of a coarse point whose empty ball holds a grid point.
void setBakeUniforms(const BakePrograms& p, const Bvh& bvh, glm::uvec3 dims, bool propagate,
                     format::SignMethod method, const GpuBakeOptions& options) {
    for (const gpu::Program* program :
         {&p.coarse, &p.distance, &p.coarseSign, &p.sign, &p.exactSign}) {
        if (program->id() == 0)
            continue;
        program->set("dims", dims);
        program->set("nodeCount", bvh.nodeCount);
    }
    p.coarse.set("bvhDepth", bvh.depth);
    if (p.distance.id() != 0)
        p.distance.set("propagate", std::uint32_t(propagate ? 1 : 0));
    for (const gpu::Program* program : {&p.coarseSign, &p.sign, &p.exactSign}) {
        if (program->id() == 0)
            continue;
        program->set("triangleCount", bvh.triangleCount);
        program->set("beta", float(options.beta));
        program->set("verifyBand", float(options.verifyBand));
        program->set("parity", std::uint32_t(method == format::SignMethod::Parity ? 1 : 0));
    }
}

} // namespace

std::string mib(std::uint64_t bytes) {
    return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}

Result<void> createStorage(std::span<const StorageAlloc> allocs) {
    for (const StorageAlloc& a : allocs) {
        Result<gpu::Buffer> buffer = gpu::Buffer::create(a.bytes, a.label);
        if (!buffer)
            return buffer.error();
        *a.buffer = std::move(*buffer);
        a.buffer->bindStorage(GLuint(a.binding));
    }
    return {};
}

std::uint64_t bvhNodeBytes(std::uint64_t triangles) {
    // buildBvh makes fewer than two nodes per triangle, 2 texels each.
    return 4 * triangles * sizeof(glm::uvec4);
}

std::uint64_t bvhTriangleBytes(std::uint64_t triangles) {
    return 3 * triangles * sizeof(glm::vec4);
}

Result<void> checkBvhFits(const std::string& sourceFile, std::uint64_t triangles,
                          const GpuBakeOptions& options) {
    const std::uint64_t maxTextureBytes =
        std::min(gpu::BufferTexture::maxTexels() * sizeof(glm::vec4),
                 options.maxBufferBytes > 0 ? options.maxBufferBytes : ~std::uint64_t(0));
    if (triangles >= kBvhMaxTriangles ||
        std::max(bvhTriangleBytes(triangles), bvhNodeBytes(triangles)) > maxTextureBytes)
        return fail(ErrorCode::SizeOverflow,
                    sourceFile + ": " + std::to_string(triangles) +
                        " triangles need GPU buffers over this GPU's largest buffer texture (" +
                        mib(maxTextureBytes) + "); simplify the mesh or use --backend cgal");
    return {};
}

Result<BakeSetup> setUpBake(const ImportedMesh& mesh, const GridSpec& grid, SignMode sign,
                            std::initializer_list<BakeLayout> layouts,
                            const std::function<Result<void>(std::uint64_t triangles)>& fits,
                            const GpuBakeOptions& options, GpuBakeStats& stats) {
    const auto start = std::chrono::steady_clock::now();
    Result<VoxelSoup> prepared = prepareVoxelSoup(mesh, grid, sign, options.phases);
    if (!prepared)
        return prepared.error();
    if (Result<void> fit = fits(prepared->triangles.size()); !fit)
        return fit.error();
    BakeSetup setup;
    setup.soup = std::move(prepared->soup);
    setup.bvh = buildBakeBvh(prepared->triangles, stats, start, options.phases);
    // The winding number is an integer off a closed surface (a cycle), so a point's sign is that
    // of any point whose empty ball holds it; an open soup's is not, so every point is pending.
    const bool propagate = setup.soup.cycle;
    for (const BakeLayout layout : layouts) {
        Result<BakePrograms> programs = compilePrograms(options.programCache, layout);
        if (!programs)
            return programs.error();
        setBakeUniforms(*programs, setup.bvh, grid.dims, propagate, setup.soup.method, options);
        setup.programs.push_back(std::move(*programs));
    }
    lap(options.phases, "gpu: compile and link programs");
    Result<GpuBvh> gpuBvh = uploadBvh(setup.bvh);
    if (!gpuBvh)
        return gpuBvh.error();
    setup.gpuBvh = std::move(*gpuBvh);
    return setup;
}

void BakePasses::distance(const gpu::Program& program, glm::uvec3 groups) {
    timed(distanceTimer, [&] { stats.dispatches += program.dispatchChunked(groups, maxGroups); });
}

void BakePasses::sign(const gpu::Program& program, std::uint32_t items,
                      std::uint64_t groupsPerDispatch) {
    program.set("itemCount", items);
    const std::uint32_t local = shared::kBakeLocalSize;
    const glm::uvec3 groups(gpu::groupCount(items, local), 1, 1);
    timed(signTimer,
          [&] { stats.dispatches += program.dispatchChunked(groups, groupsPerDispatch); });
}

void BakePasses::readTimes() {
    if (!distanceTimer)
        return;
    if (distanceTimer->completed() > 0 || distanceTimer->pending() > 0) {
        (void)distanceTimer->elapsedNs();
        stats.distanceNs = distanceTimer->totalNs();
    }
    if (signTimer->completed() > 0 || signTimer->pending() > 0) {
        (void)signTimer->elapsedNs();
        stats.signNs = signTimer->totalNs();
    }
}

BakePasses makePasses(GpuBakeStats& stats, const GpuBakeOptions& options,
                      std::uint32_t triangleCount) {
    BakePasses passes{stats};
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

std::uint64_t pendingBytes(std::uint64_t blocks) {
    return sizeof(shared::PendingHeader) + blocks * sizeof(glm::uvec2);
}

std::uint64_t verifyBytes(std::uint64_t blocks) {
    return sizeof(shared::PendingHeader) +
           blocks * 4 * shared::kBakeBlockDepth * sizeof(std::uint32_t);
}

void runSlabs(BakePasses& passes, const BakePrograms& programs, const SignLists& lists,
              const SlabPlan& plan, Progress* progress) {
    std::uint32_t slabLayers = plan.firstLayers;
    for (std::uint32_t z0 = 0, z1 = 0; z0 < plan.layers; z0 = z1) {
        const auto slabStart = std::chrono::steady_clock::now();
        z1 = std::min(plan.layers, z0 + slabLayers);
        const shared::PendingHeader empty{};
        lists.pending.upload(&empty, sizeof(empty));
        lists.verify.upload(&empty, sizeof(empty));
        programs.distance.set("groupBegin", z0);
        const glm::uvec3 groups = plan.alongX
                                      ? glm::uvec3(z1 - z0, plan.layerGroups.x, plan.layerGroups.y)
                                      : glm::uvec3(plan.layerGroups.x, plan.layerGroups.y, z1 - z0);
        passes.distance(programs.distance, groups);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        signPendingPoints(passes, programs, lists);
        if (progress && plan.pointsOf)
            progress->add(plan.pointsOf(z0, z1));
        slabLayers = nextSlabLayers(z1 - z0, secondsSince(slabStart), plan.maxLayers);
    }
}

} // namespace sluice::bake
