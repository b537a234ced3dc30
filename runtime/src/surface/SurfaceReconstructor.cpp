// The surface passes: mark the blocks the particles reach, number them, splat the field into
// them, count each block's vertices and triangles, number those, write them (docs/surfaces.md).
#include "sluice/rt/surface/SurfaceMesh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "grid/PrefixScan.h"
#include "shared/Surface.h"
#include "sluice/gpu/Program.h"
#include "sluice/rt/RuntimeShaders.h"
#include "surface/CubeTable.h"
#include "surface/SurfaceBlur.h"
#include "surface/SurfaceGpu.h"
#include "surface/SurfaceGrid.h"

namespace sluice::rt {
namespace {

namespace sh = shared;
using namespace surface;

enum Pass : std::size_t {
    Bounds,
    BinCount,
    BinFill,
    Anisotropy,
    Mark,
    Compact,
    Splat,
    Deposit,
    Density,
    Count,
    Vertices,
    Triangles,
    PassCount
};
constexpr std::array<const char*, PassCount> kPassFiles = {
    "surface_bounds.comp",     "surface_bin_count.comp", "surface_bin_fill.comp",
    "surface_anisotropy.comp", "surface_mark.comp",      "surface_compact.comp",
    "surface_splat.comp",      "surface_deposit.comp",   "surface_density.comp",
    "surface_count.comp",      "surface_vertices.comp",  "surface_triangles.comp"};

std::uint32_t readUint(const gpu::Buffer& buffer, std::uint64_t index) {
    std::uint32_t value = 0;
    buffer.download(&value, sizeof value, index * sizeof value);
    return value;
}

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

} // namespace

/// The buffers of the reconstructions, kept from one to the next (ensureBytes), and the
/// counts and stage times of the latest.
struct Work {
    gpu::Buffer flags, slots, active, field;
    gpu::Buffer blockVerts, blockTris, vertBase, triBase, sampleVert, sampleCode;
    gpu::Buffer positions, normals, triangles;
    gpu::Buffer bounds;                                               ///< shared::SurfaceBounds
    gpu::Buffer binCount, binStart, binParticles, binPoints, kernels; ///< anisotropic only
    gpu::Buffer weights; ///< densityNormalised only: each particle's weight
    std::uint32_t activeBlocks = 0;
    std::uint32_t vertexCount = 0;
    std::uint32_t triangleCount = 0;
    SurfaceTimings timings;
};

struct SurfaceReconstructor::Impl {
    std::array<gpu::Program, PassCount> passes;
    std::optional<PrefixScan> scan;
    gpu::Buffer triangleTable; ///< cellTriangleTable()
    std::uint32_t scanCapacity = 0;
    Work work;

    GaussianBlurPasses blurPasses;

    const gpu::Program& pass(Pass p) const { return passes[p]; }

    Result<void> ensureScan(std::uint64_t count) {
        if (scan && count <= scanCapacity)
            return {};
        auto created = PrefixScan::create(std::uint32_t(count));
        if (!created)
            return created.error();
        scan.emplace(std::move(*created));
        scanCapacity = std::uint32_t(count);
        return {};
    }

    void setGrid(const SurfaceGrid& g, const SurfaceOptions& o) const {
        for (const gpu::Program& p : passes)
            setGridUniforms(p, g, o);
        pass(Anisotropy).set("uCentreSmoothing", o.centreSmoothing.value_or(0.0f));
    }

    Result<void> kernels(const gpu::Buffer& positions, std::uint32_t count, const SurfaceGrid& g,
                         Work& work);
    Result<void> field(const gpu::Buffer& positions, std::uint32_t count, const SurfaceGrid& g,
                       const SurfaceOptions& o, Work& work);
    Result<void> fieldPass(std::uint32_t count, const SurfaceGrid& g, const SurfaceOptions& o,
                           Work& work, bool weighted);
    Result<void> contour(Work& work);
    Result<std::pair<glm::vec3, glm::vec3>> bounds(const gpu::Buffer& positions,
                                                   std::uint32_t count);
    Result<SurfaceMesh> download(const SurfaceGpuMesh& built);
};

/// Anisotropic kernels: sorts the particles into the grid's blocks (count, scan, fill) and
/// writes every particle's kernel from its neighbours (surface_anisotropy.comp).
Result<void> SurfaceReconstructor::Impl::kernels(const gpu::Buffer& positions, std::uint32_t count,
                                                 const SurfaceGrid& g, Work& w) {
    const auto start = Clock::now();
    if (auto ok = ensureUints(w.binCount, g.blockCount, "surface bin counts"); !ok)
        return ok;
    // The scan, the fill and the kernels' pass write every entry of the other three.
    if (auto ok = ensureUints(w.binStart, g.blockCount, "surface bin starts", false); !ok)
        return ok;
    if (auto ok = ensureUints(w.binParticles, count, "surface bin particles", false); !ok)
        return ok;
    if (auto ok = ensureUints(w.binPoints, 4 * std::uint64_t(count), "surface bin points", false);
        !ok)
        return ok;
    if (auto ok = ensureUints(w.kernels, 16 * std::uint64_t(count), "surface kernels", false); !ok)
        return ok;
    if (auto ok = ensureScan(g.blockCount); !ok)
        return ok;
    const glm::uvec3 groups(gpu::groupCount(count, sh::kSurfaceLocalSize), 1, 1);
    positions.bindStorage(sh::kSurfBindPoints);
    w.binCount.bindStorage(sh::kSurfBindBinCount);
    pass(BinCount).set("uCount", count);
    pass(BinCount).dispatchChunked(groups, kMaxGroupsPerDispatch);
    barrier();
    scan->exclusive(w.binCount, w.binStart, std::uint32_t(g.blockCount));
    barrier();
    positions.bindStorage(sh::kSurfBindPoints);
    w.binCount.bindStorage(sh::kSurfBindBinCount);
    w.binStart.bindStorage(sh::kSurfBindBinStart);
    w.binParticles.bindStorage(sh::kSurfBindBinParticles);
    w.binPoints.bindStorage(sh::kSurfBindBinPoints);
    w.kernels.bindStorage(sh::kSurfBindKernels);
    pass(BinFill).set("uCount", count);
    pass(BinFill).dispatchChunked(groups, kMaxGroupsPerDispatch);
    barrier();
    pass(Anisotropy).set("uCount", count);
    pass(Anisotropy).set("uBinCount", std::uint32_t(g.blockCount));
    pass(Anisotropy).dispatchChunked(groups, kMaxGroupsPerDispatch);
    barrier();
    glFinish();
    w.timings.kernels = millisecondsSince(start);
    return {};
}

/// Adds every particle's kernel, scaled by its weight when `weighted`, to the zeroed field: the
/// Gaussian's deposit and blur, or the poly6 splat.
Result<void> SurfaceReconstructor::Impl::fieldPass(std::uint32_t count, const SurfaceGrid& g,
                                                   const SurfaceOptions& o, Work& w,
                                                   bool weighted) {
    const std::optional<SurfaceBlur> gaussian = gaussianBlur(o);
    const gpu::Program& p = pass(gaussian ? Deposit : Splat);
    p.set("uCount", count);
    p.set("uWeighted", std::int32_t(weighted ? 1 : 0));
    p.dispatchChunked(glm::uvec3(gpu::groupCount(count, sh::kSurfaceLocalSize), 1, 1),
                      kMaxGroupsPerDispatch);
    barrier();
    if (gaussian)
        return blurPasses.run(*gaussian, g, o, w.field, w.activeBlocks);
    return {};
}

/// Marks the blocks, numbers them, and makes the field: the Gaussian's deposit and blur, or
/// every particle's poly6 splatted (its kernel from `kernels` when anisotropic).
Result<void> SurfaceReconstructor::Impl::field(const gpu::Buffer& positions, std::uint32_t count,
                                               const SurfaceGrid& g, const SurfaceOptions& o,
                                               Work& w) {
    const bool anisotropic = o.anisotropic;
    if (anisotropic) {
        if (auto ok = kernels(positions, count, g, w); !ok)
            return ok;
    }
    auto start = Clock::now();
    if (auto ok = ensureUints(w.flags, g.blockCount, "surface block flags"); !ok)
        return ok;
    if (auto ok = ensureUints(w.slots, g.blockCount, "surface block slots"); !ok)
        return ok;
    if (auto ok = ensureScan(g.blockCount); !ok)
        return ok;
    positions.bindStorage(sh::kSurfBindPoints);
    // Read only when anisotropic; something is bound either way.
    (anisotropic ? w.kernels : positions).bindStorage(sh::kSurfBindKernels);
    w.flags.bindStorage(sh::kSurfBindBlockFlag);
    const std::uint32_t particleGroups = gpu::groupCount(count, sh::kSurfaceLocalSize);
    pass(Mark).set("uCount", count);
    pass(Mark).dispatchChunked(glm::uvec3(particleGroups, 1, 1), kMaxGroupsPerDispatch);
    barrier();
    scan->exclusive(w.flags, w.slots, std::uint32_t(g.blockCount));
    barrier();
    w.activeBlocks = readUint(w.slots, g.blockCount - 1) + readUint(w.flags, g.blockCount - 1);
    w.timings.blocks = millisecondsSince(start);
    start = Clock::now();
    if (auto ok = ensureUints(w.active, w.activeBlocks, "surface blocks"); !ok)
        return ok;
    if (auto ok = ensureUints(w.field, std::uint64_t(w.activeBlocks) * sh::kSurfaceBlockSamples,
                              "surface field");
        !ok)
        return ok;
    w.flags.bindStorage(sh::kSurfBindBlockFlag);
    w.slots.bindStorage(sh::kSurfBindBlockSlot);
    w.active.bindStorage(sh::kSurfBindActive);
    w.field.bindStorage(sh::kSurfBindField);
    pass(Compact).set("uCount", std::uint32_t(g.blockCount));
    pass(Compact).dispatchChunked(
        glm::uvec3(gpu::groupCount(g.blockCount, sh::kSurfaceLocalSize), 1, 1),
        kMaxGroupsPerDispatch);
    positions.bindStorage(sh::kSurfBindPoints);
    (anisotropic ? w.kernels : positions).bindStorage(sh::kSurfBindKernels);
    // Read only in the density-normalised field's second pass; something is bound either way.
    positions.bindStorage(sh::kSurfBindWeights);
    if (auto ok = fieldPass(count, g, o, w, false); !ok)
        return ok;
    if (isDensityNormalised(o)) {
        // Each particle's density from the field, then the field again with its weight.
        if (auto ok = ensureUints(w.weights, count, "surface weights", false); !ok)
            return ok;
        w.weights.bindStorage(sh::kSurfBindWeights);
        pass(Density).set("uCount", count);
        pass(Density).dispatchChunked(glm::uvec3(particleGroups, 1, 1), kMaxGroupsPerDispatch);
        barrier();
        w.field.clear(0, std::uint64_t(w.activeBlocks) * sh::kSurfaceBlockSamples * 4);
        barrier();
        if (auto ok = fieldPass(count, g, o, w, true); !ok)
            return ok;
    }
    glFinish(); // so that the splat's time is its own, not the contour's
    w.timings.field = millisecondsSince(start);
    return {};
}

/// Counts, numbers and writes the vertices and triangles of the stored blocks.
Result<void> SurfaceReconstructor::Impl::contour(Work& w) {
    const auto start = Clock::now();
    const std::uint32_t n = w.activeBlocks;
    const std::uint64_t samples = std::uint64_t(n) * sh::kSurfaceBlockSamples;
    const char* labels[] = {"surface block vertices",  "surface block triangles",
                            "surface vertex bases",    "surface triangle bases",
                            "surface sample vertices", "surface sample codes"};
    gpu::Buffer* targets[] = {&w.blockVerts, &w.blockTris,  &w.vertBase,
                              &w.triBase,    &w.sampleVert, &w.sampleCode};
    for (std::size_t i = 0; i < 6; ++i)
        if (auto ok = ensureUints(*targets[i], i < 4 ? n : samples, labels[i]); !ok)
            return ok;
    const glm::uvec3 groups(n, 1, 1);
    triangleTable.bindStorage(sh::kSurfBindTriangleTable);
    w.blockVerts.bindStorage(sh::kSurfBindBlockVerts);
    w.blockTris.bindStorage(sh::kSurfBindBlockTris);
    w.sampleCode.bindStorage(sh::kSurfBindSampleCode);
    pass(Count).set("uCount", n);
    pass(Count).dispatchChunked(groups, kMaxGroupsPerDispatch);
    barrier();
    if (auto ok = ensureScan(n); !ok)
        return ok;
    scan->exclusive(w.blockVerts, w.vertBase, n);
    scan->exclusive(w.blockTris, w.triBase, n);
    barrier();
    w.vertexCount = readUint(w.vertBase, n - 1) + readUint(w.blockVerts, n - 1);
    w.triangleCount = readUint(w.triBase, n - 1) + readUint(w.blockTris, n - 1);
    for (auto [buffer, label] :
         {std::pair{&w.positions, "surface positions"}, std::pair{&w.normals, "surface normals"}})
        if (auto ok = ensureBytes(*buffer, std::uint64_t(w.vertexCount) * 12, label, false); !ok)
            return ok;
    if (auto ok = ensureUints(w.triangles, 3 * std::uint64_t(w.triangleCount), "surface triangles");
        !ok)
        return ok;
    // The scans bound their own buffers: bind the grid's again.
    w.flags.bindStorage(sh::kSurfBindBlockFlag);
    w.slots.bindStorage(sh::kSurfBindBlockSlot);
    w.active.bindStorage(sh::kSurfBindActive);
    w.field.bindStorage(sh::kSurfBindField);
    w.vertBase.bindStorage(sh::kSurfBindVertBase);
    w.triBase.bindStorage(sh::kSurfBindTriBase);
    w.sampleVert.bindStorage(sh::kSurfBindSampleVert);
    w.sampleCode.bindStorage(sh::kSurfBindSampleCode);
    w.positions.bindStorage(sh::kSurfBindPositions);
    w.normals.bindStorage(sh::kSurfBindNormals);
    w.triangles.bindStorage(sh::kSurfBindTriangles);
    triangleTable.bindStorage(sh::kSurfBindTriangleTable);
    pass(Vertices).set("uCount", n);
    pass(Vertices).dispatchChunked(groups, kMaxGroupsPerDispatch);
    barrier();
    pass(Triangles).set("uCount", n);
    pass(Triangles).dispatchChunked(groups, kMaxGroupsPerDispatch);
    barrier();
    glFinish();
    w.timings.contour = millisecondsSince(start);
    return {};
}

/// Reads `built` back: each array copied straight into its vector (the GPU wrote them in the
/// vectors' layout).
Result<SurfaceMesh> SurfaceReconstructor::Impl::download(const SurfaceGpuMesh& built) {
    SurfaceMesh mesh;
    mesh.gridOrigin = built.gridOrigin;
    mesh.cellSize = built.cellSize;
    mesh.storedSamples = built.storedSamples;
    mesh.timings = built.timings;
    if (built.triangleCount == 0 && built.vertexCount == 0)
        return mesh;
    static_assert(sizeof(glm::vec3) == 12 && sizeof(glm::uvec3) == 12);
    mesh.vertices.resize(built.vertexCount);
    mesh.normals.resize(built.vertexCount);
    mesh.triangles.resize(built.triangleCount);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    built.positions->download(mesh.vertices.data(), mesh.vertices.size() * 12);
    built.normals->download(mesh.normals.data(), mesh.normals.size() * 12);
    built.triangles->download(mesh.triangles.data(), mesh.triangles.size() * 12);
    return mesh;
}

SurfaceReconstructor::SurfaceReconstructor(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
SurfaceReconstructor::SurfaceReconstructor(SurfaceReconstructor&&) noexcept = default;
SurfaceReconstructor& SurfaceReconstructor::operator=(SurfaceReconstructor&&) noexcept = default;
SurfaceReconstructor::~SurfaceReconstructor() = default;

Result<SurfaceReconstructor> SurfaceReconstructor::create() {
    auto impl = std::make_unique<Impl>();
    for (std::size_t p = 0; p < PassCount; ++p) {
        auto program = gpu::Program::compute(kPassFiles[p], shaders::shaderSource(kPassFiles[p]));
        if (!program)
            return program.error();
        impl->passes[p] = std::move(*program);
    }
    static_assert(kCellTrianglesMax == sh::kSurfaceCellTrianglesMax);
    auto table = gpu::Buffer::createFrom(cellTriangleTable(), "surface triangle table");
    if (!table)
        return table.error();
    impl->triangleTable = std::move(*table);
    // The blur of the default options, so that a first reconstruction does not compile it.
    SurfaceOptions defaults;
    defaults.particleRadius = 1.0f;
    if (auto resolved = resolveSurfaceOptions(defaults))
        if (auto blur = gaussianBlur(*resolved))
            if (auto ok = impl->blurPasses.prepare(blur->radius); !ok)
                return ok.error();
    return SurfaceReconstructor(std::move(impl));
}

/// The particles' box on the GPU (surface_bounds.comp): lo and hi, or InvalidArgument naming
/// the first non-finite particle.
Result<std::pair<glm::vec3, glm::vec3>>
SurfaceReconstructor::Impl::bounds(const gpu::Buffer& positions, std::uint32_t count) {
    if (work.bounds.size() == 0) {
        auto created = gpu::Buffer::create(sizeof(sh::SurfaceBounds), "surface bounds");
        if (!created)
            return created.error();
        work.bounds = std::move(*created);
    }
    const sh::SurfaceBounds empty{{~0u, ~0u, ~0u}, {0u, 0u, 0u}, 0u, ~0u};
    work.bounds.upload(&empty, sizeof empty);
    positions.bindStorage(sh::kSurfBindPoints);
    work.bounds.bindStorage(sh::kSurfBindBounds);
    pass(Bounds).set("uCount", count);
    pass(Bounds).dispatchChunked(glm::uvec3(gpu::groupCount(count, sh::kSurfaceLocalSize), 1, 1),
                                 kMaxGroupsPerDispatch);
    barrier();
    sh::SurfaceBounds b{};
    work.bounds.download(&b, sizeof b);
    if (b.nonFinite > 0)
        return fail(ErrorCode::InvalidArgument,
                    "surface: particle " + std::to_string(b.firstNonFinite) + " is not finite" +
                        (b.nonFinite > 1 ? " (and " + std::to_string(b.nonFinite - 1) + " more)"
                                         : std::string()));
    const auto value = [](std::uint32_t bits) {
        const std::uint32_t u = (bits & 0x80000000u) != 0 ? bits & 0x7fffffffu : ~bits;
        return std::bit_cast<float>(u);
    };
    return std::pair{glm::vec3(value(b.lo[0]), value(b.lo[1]), value(b.lo[2])),
                     glm::vec3(value(b.hi[0]), value(b.hi[1]), value(b.hi[2]))};
}

Result<SurfaceGpuMesh> SurfaceReconstructor::build(const gpu::Buffer& positions,
                                                   std::uint32_t count,
                                                   const SurfaceOptions& options) {
    auto o = resolveSurfaceOptions(options);
    if (!o)
        return o.error();
    if (count == 0)
        return SurfaceGpuMesh{.cellSize = o->cellSize};
    SLUICE_ASSERT(positions.size() >= std::size_t(count) * 16,
                  "SurfaceReconstructor: fewer positions than count");
    const auto start = Clock::now();
    // The bounds size the grid; non-finite positions are refused before they do.
    const auto box = m_impl->bounds(positions, count);
    if (!box)
        return box.error();
    auto grid = gridOver(box->first, box->second, *o);
    if (!grid)
        return grid.error();
    m_impl->setGrid(*grid, *o);
    Work& work = m_impl->work;
    work.activeBlocks = work.vertexCount = work.triangleCount = 0;
    work.timings = {};
    work.timings.bounds = millisecondsSince(start);
    if (auto ok = m_impl->field(positions, count, *grid, *o, work); !ok)
        return ok.error();
    SurfaceGpuMesh mesh{.gridOrigin = grid->origin,
                        .cellSize = o->cellSize,
                        .storedSamples =
                            std::uint64_t(work.activeBlocks) * sh::kSurfaceBlockSamples};
    if (work.activeBlocks > 0) {
        if (auto ok = m_impl->contour(work); !ok)
            return ok.error();
        mesh.positions = &work.positions;
        mesh.normals = &work.normals;
        mesh.triangles = &work.triangles;
        mesh.vertexCount = work.vertexCount;
        mesh.triangleCount = work.triangleCount;
    }
    mesh.timings = work.timings;
    return mesh;
}

Result<SurfaceMesh> SurfaceReconstructor::reconstruct(const gpu::Buffer& positions,
                                                      std::uint32_t count,
                                                      const SurfaceOptions& options) {
    auto built = build(positions, count, options);
    if (!built)
        return built.error();
    const auto start = Clock::now();
    auto mesh = m_impl->download(*built);
    if (!mesh)
        return mesh.error();
    mesh->timings.download = millisecondsSince(start);
    return mesh;
}

Result<SurfaceMesh> SurfaceReconstructor::reconstruct(std::span<const glm::vec3> points,
                                                      const SurfaceOptions& options) {
    if (points.size() > std::numeric_limits<std::uint32_t>::max() / 16)
        return fail(ErrorCode::SizeOverflow, "surface: " + std::to_string(points.size()) +
                                                 " particles are more than a buffer holds");
    std::vector<glm::vec4> padded;
    padded.reserve(points.size());
    for (const glm::vec3& p : points)
        padded.emplace_back(p, 1.0f);
    if (padded.empty())
        padded.emplace_back(0.0f);
    auto buffer = gpu::Buffer::createFrom(padded, "surface points");
    if (!buffer)
        return buffer.error();
    return reconstruct(*buffer, std::uint32_t(points.size()), options);
}

} // namespace sluice::rt
