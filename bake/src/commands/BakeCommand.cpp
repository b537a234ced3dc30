// `sluice-bake bake`: mesh (or level-set .vdb) in, collider asset out, with a short summary.
#include <chrono>
#include <ctime>
#include <future>
#include <iostream>
#include <optional>

#include "commands/CliSupport.h"
#include "jobs/PhaseReport.h"
#include "sluice/bake/Grid.h"
#include "sluice/bake/cgal/CgalBaker.h"
#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/cgal/CgalSparseBaker.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/bake/gpu/GpuBaker.h"
#include "sluice/bake/gpu/GpuSparseBaker.h"
#include "sluice/bake/jobs/BakeJob.h"
#include "sluice/bake/sparse/SparseBaker.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/support/AtomicFile.h"
#include "sluice/gpu/Context.h"

namespace sluice::bake::cli {
namespace {

/// Where the distances are computed: the GPU baker, the exact CPU reference, or (the default)
/// the GPU where a GL 4.5 context opens and the CPU reference otherwise. Both give the same
/// exact field; the asset records the one that ran.
enum class Backend { Auto, Gpu, Cgal };

/// The backend named `text`, one bakeSettingsFor accepted ("auto", "gpu" or "cgal").
Backend backendNamed(const std::string& text) {
    return text == "gpu" ? Backend::Gpu : text == "cgal" ? Backend::Cgal : Backend::Auto;
}

constexpr std::string_view kCmd = "bake";

/// [s] CPU time of the calling thread.
double threadCpuSeconds() {
    timespec t{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/// The self-intersection test of the mesh diagnostics, run on a worker thread while the GPU
/// context opens and the GPU bakes (it costs more than the rest of the diagnostics together).
struct SelfIntersectionTest {
    bool found = false;
    double wallSeconds = 0.0; ///< [s]
    double cpuSeconds = 0.0;  ///< [s] of the worker thread
    std::optional<Error> error;
};

/// One bake on its way from arguments to a written asset; each step fills in its part.
struct BakeJob {
    Backend backend = Backend::Auto; ///< Gpu or Cgal once openBackend ran
    BakeSettings settings;
    std::optional<ImportedMesh> mesh;
    /// While it runs, mesh->diagnostics.selfIntersecting is false, not yet known.
    std::future<SelfIntersectionTest> selfIntersection;
    BakeRequest request;      ///< the arguments as the library takes them
    Box meshBox;              ///< [world units] the scaled mesh's bounding box
    double band = 0.0;        ///< [voxels] sparse: --band, or the one --for-spacing picked
    std::uint64_t points = 0; ///< [grid points] of the grid to bake
    std::optional<Result<gpu::Context>> contextResult; ///< opened during the import
    std::optional<gpu::Context> context;
    std::optional<gpu::ProgramCache> programCache;
    std::string renderer;
    GpuBakeStats gpuStats;
    std::optional<format::ColliderAsset> asset;
    SparseBakeStats sparseStats;
    std::size_t bytes = 0; ///< [bytes] of the written file
    double importSeconds = 0.0;
    double bakeSeconds = 0.0;
    PhaseLog phases{"start-up (exec, libraries, parsing the arguments)"};
};

/// Every argument is checked, and OUT's folder created, before the mesh is read, so mistakes
/// fail fast. An OUT not ending in .slc is written anyway, with a warning.
int checkArguments(const BakeArgs& args, BakeJob& job) {
    BakeRequest request;
    request.backend = args.backend;
    request.resolution = args.resolution;
    request.voxelSize = args.voxelSize;
    request.padding = args.padding;
    request.sign = args.sign;
    request.storage = args.storage;
    request.scale = args.scale;
    request.sparse = args.sparse;
    request.band = args.band;
    request.forSpacing = args.forSpacing;
    request.forKernelRadius = args.forKernelRadius;
    request.volumeMaps = args.volumeMaps;
    if (Result<void> maps = checkVolumeMapSupports(args.volumeMaps); !maps)
        return reportBadInput(kCmd, "--volume-map: " + maps.error().detail);
    // bakeSettingsFor checks the backend first: an unknown one is refused here.
    Result<BakeSettings> settings = bakeSettingsFor(request);
    if (!settings)
        return reportBadInput(kCmd, settings.error().detail);
    if (Result<void> out = prepareOutputPath(args.output); !out)
        return reportFileError(kCmd, "cannot write", args.output, out.error());
    if (args.sparse && settings->storage != format::Storage::F32)
        return reportBadInput(kCmd, "--sparse stores f32 values; leave out --storage f16");
    if (!hasExtension(args.output, ".slc"))
        std::cerr << "sluice-bake bake: warning: '" << args.output
                  << "' does not end in .slc; it will hold a collider asset all the same\n";
    job.backend = backendNamed(args.backend);
    job.settings = *settings;
    job.request = request;
    job.phases.lap("argument checks");
    return kExitOk;
}

/// Runs the self-intersection test of `soup`, which must outlive it, on a new thread.
std::future<SelfIntersectionTest> startSelfIntersectionTest(const TriangleSoup& soup) {
    return std::async(std::launch::async, [&soup] {
        SelfIntersectionTest test;
        const auto start = std::chrono::steady_clock::now();
        const double cpu = threadCpuSeconds();
        // As inside importMesh: CGAL and allocation failures are errors of this mesh.
        try {
            test.found = selfIntersects(soup);
        } catch (const std::bad_alloc&) {
            test.error = Error{ErrorCode::SizeOverflow, "out of memory while diagnosing the mesh"};
        } catch (const std::exception& e) {
            test.error = Error{ErrorCode::MeshImport,
                               std::string("the self-intersection test failed (") + e.what() + ")"};
        }
        test.wallSeconds = secondsSince(start);
        test.cpuSeconds = threadCpuSeconds() - cpu;
        return test;
    });
}

/// Waits for the self-intersection test, if one runs, and puts its answer into the mesh's
/// diagnostics. The lap is the wait; the test's own time goes in as an overlapped phase.
int awaitSelfIntersectionTest(const BakeArgs& args, BakeJob& job) {
    if (!job.selfIntersection.valid())
        return kExitOk;
    const SelfIntersectionTest test = job.selfIntersection.get();
    job.phases.addOverlapped("mesh diagnostics: self-intersection test", test.wallSeconds,
                             test.cpuSeconds);
    job.phases.lap("wait for the self-intersection test");
    if (test.error)
        return reportFileError(kCmd, "cannot read mesh", args.mesh, *test.error);
    job.mesh->diagnostics.selfIntersecting = test.found;
    return kExitOk;
}

/// Tries to open the GL context and the program cache, for openBackend to judge: an error here
/// is reported only once the import has succeeded, as if the context came after it.
void openContext(const BakeArgs& args, BakeJob& job) {
    job.phases.lap("import: start the isolated child");
    job.contextResult.emplace(gpu::Context::createHeadless());
    job.phases.lap("GPU context (while the child reads the mesh)");
    if (*job.contextResult) {
        job.programCache.emplace(gpu::ProgramCache::open({.enabled = args.programCache}));
        job.phases.lap("program cache");
    }
}

/// Reads the mesh at its scale and lays the grid over it. Where the GPU may bake, the GL
/// context opens while the isolated child reads the file (openContext), and the
/// self-intersection test of the diagnostics starts on a worker thread after (see bakeOnGpu).
int importAndPlan(const BakeArgs& args, BakeJob& job) {
    const auto start = std::chrono::steady_clock::now();
    const bool maybeGpu = job.backend != Backend::Cgal;
    ImportOptions options;
    options.scale = args.scale;
    options.phases = &job.phases;
    options.selfIntersectionTest = !maybeGpu;
    if (maybeGpu)
        options.whileImporting = [&] { openContext(args, job); };
    const bool deferred = maybeGpu && !isLevelSetFile(args.mesh);
    Result<ImportedMesh> mesh = loadMesh(args.mesh, options);
    if (!mesh)
        return reportFileError(kCmd, "cannot read mesh", args.mesh, mesh.error());
    job.importSeconds = secondsSince(start);
    job.meshBox = mesh->soup.bounds();
    const Result<double> band = requestBand(job.request, job.meshBox, job.settings.grid);
    if (!band)
        return reportFileError(kCmd, "cannot bake", args.mesh, band.error());
    job.band = *band;
    Result<GridSpec> grid = args.sparse ? sparseGridFor(job.meshBox, job.settings.grid, job.band)
                                        : gridFor(job.meshBox, job.settings.grid);
    if (!grid)
        return reportFileError(kCmd, "cannot bake", args.mesh, grid.error());
    job.points = grid->pointCount();
    job.mesh = std::move(*mesh);
    if (deferred)
        job.selfIntersection = startSelfIntersectionTest(job.mesh->soup);
    job.phases.lap("grid plan");
    return kExitOk;
}

/// Resolves auto to gpu where a GL 4.5 context opens, else to cgal; gpu without a context fails.
int openBackend(const BakeArgs& args, BakeJob& job) {
    if (job.backend == Backend::Cgal)
        return kExitOk;
    if (!job.contextResult)
        openContext(args, job);
    Result<gpu::Context> context = std::move(*job.contextResult);
    job.contextResult.reset();
    if (!context && job.backend == Backend::Gpu)
        return reportError(kCmd, "no GPU context for --backend gpu (use --backend cgal)",
                           context.error());
    if (!context) {
        // auto: the same exact field from the CPU reference, only slower.
        std::cerr << "sluice-bake bake: no OpenGL 4.5 context (" << context.error().detail
                  << "); baking on the CPU with the CGAL backend\n";
        job.backend = Backend::Cgal;
        return kExitOk;
    }
    job.backend = Backend::Gpu;
    job.context.emplace(std::move(*context));
    job.renderer = job.context->info().renderer;
    return kExitOk;
}

/// The GPU bake, started before the self-intersection test has answered. Only the sign method
/// of `--sign auto` on a closed mesh depends on the answer (parity, or the winding number for a
/// mesh that intersects itself), so the bake assumes the common case, parity, and bakes again
/// with the winding number in the rare other one: the same asset as waiting would give.
Result<format::ColliderAsset> bakeOnGpu(const BakeArgs& args, BakeJob& job, int& code) {
    const auto bake = [&]() {
        const GpuBakeOptions options{
            .profile = args.profile, .programCache = &*job.programCache, .phases = &job.phases};
        if (args.sparse)
            return bakeSparseGpu(*job.mesh, job.settings, {.band = job.band}, *job.context,
                                 !args.quiet, options, &job.gpuStats, &job.sparseStats);
        Progress progress("baking " + job.mesh->sourceFile + " on the GPU", job.points,
                          !args.quiet);
        Result<format::ColliderAsset> asset =
            bakeGpu(*job.mesh, job.settings, *job.context, &progress, options, &job.gpuStats);
        progress.finish();
        job.phases.lap("gpu: progress report");
        return asset;
    };
    Result<format::ColliderAsset> asset = bake();
    if (!asset || !job.selfIntersection.valid())
        return asset;
    if ((code = awaitSelfIntersectionTest(args, job)) != kExitOk)
        return asset;
    const format::MeshDiagnostics& diagnostics = job.mesh->diagnostics;
    if (diagnostics.selfIntersecting && diagnostics.closed && job.settings.sign == SignMode::Auto)
        return bake();
    asset->meta.mesh = diagnostics;
    return asset;
}

/// Computes the field on the chosen backend, with a progress bar unless --quiet.
int bakeField(const BakeArgs& args, BakeJob& job) {
    const auto start = std::chrono::steady_clock::now();
    std::optional<Result<format::ColliderAsset>> asset;
    if (job.backend != Backend::Gpu)
        if (const int code = awaitSelfIntersectionTest(args, job); code != kExitOk)
            return code;
    const ImportedMesh& mesh = *job.mesh;
    if (job.backend == Backend::Gpu) {
        int code = kExitOk;
        asset.emplace(bakeOnGpu(args, job, code));
        if (code != kExitOk)
            return code;
    } else if (args.sparse) {
        asset.emplace(
            bakeSparseCgal(mesh, job.settings, {.band = job.band}, !args.quiet, &job.sparseStats));
    } else {
        Progress progress("baking " + mesh.sourceFile, job.points, !args.quiet);
        asset.emplace(bakeCgal(mesh, job.settings, &progress));
        progress.finish();
    }
    if (!asset->ok())
        return reportFileError(kCmd, "cannot bake", args.mesh, asset->error());
    job.bakeSeconds = secondsSince(start);
    job.asset.emplace(std::move(asset->value()));
    if (job.backend != Backend::Gpu)
        job.phases.lap(args.sparse ? "sparse bake (cgal)" : "cgal bake");
    if (!args.volumeMaps.empty()) {
        if (Result<void> maps =
                bakeVolumeMaps(*job.asset, args.volumeMaps, job.context.has_value());
            !maps)
            return reportFileError(kCmd, "cannot bake the volume maps of", args.mesh, maps.error());
        job.phases.lap("volume maps");
    }
    if (job.context) {
        // Now rather than at exit, so the profile sees it (eglTerminate joins llvmpipe's threads).
        job.context.reset();
        job.phases.lap("release the GPU context");
    }
    return kExitOk;
}

/// Encodes first and writes atomically after: a failed bake or encode leaves OUT untouched.
int writeOutput(const BakeArgs& args, BakeJob& job) {
    Result<format::EncodedAsset> encoded = format::encodeAsset(*job.asset);
    if (!encoded)
        return reportFileError(kCmd, "cannot encode the asset for", args.output, encoded.error());
    job.asset->meta.quantizationError = encoded->quantizationError;
    job.phases.lap("encode");
    if (Result<void> written = format::writeFileAtomic(args.output, encoded->bytes); !written)
        return reportFileError(kCmd, "cannot write", args.output, written.error());
    job.bytes = encoded->bytes.size();
    job.phases.lap("write (atomic, fsync)");
    return kExitOk;
}

/// [grid points / s] of the bake (dense), [band voxels computed / s] (sparse).
double pointsPerSecond(const BakeJob& job) {
    const double points = job.asset->sparse() ? double(job.sparseStats.voxelsComputed)
                                              : double(job.asset->pointCount());
    return job.bakeSeconds > 0.0 ? points / job.bakeSeconds : 0.0;
}

/// The sparse bake's work and memory, for the summary and JSON.
nlohmann::ordered_json sparseJson(const BakeJob& job) {
    const SparseBakeStats& s = job.sparseStats;
    return {{"band", job.asset->meta.bandWidth},
            {"bricks", s.bricks},
            {"uniformBlocks", s.uniformBlocks},
            {"voxelsComputed", s.voxelsComputed},
            {"distanceQueries", s.distanceQueries},
            {"activeVoxels", s.activeVoxels},
            {"gridBytes", s.gridBytes},
            {"planSeconds", s.planSeconds},
            {"distanceSeconds", s.distanceSeconds},
            {"buildSeconds", s.buildSeconds},
            {"peakRssBytes", peakRssBytes()}};
}

/// What the program cache did: {"enabled", "offReason", "dir", "binaryFormats", "hits",
/// "misses", "stored", "rejected"}.
nlohmann::ordered_json programCacheJson(const gpu::ProgramCache& cache) {
    const gpu::ProgramCacheStats& s = cache.stats();
    return {{"enabled", cache.enabled()},
            {"offReason", cache.offReason()},
            {"dir", cache.dir().string()},
            {"binaryFormats", cache.binaryFormats()},
            {"hits", s.hits},
            {"misses", s.misses},
            {"stored", s.stored},
            {"rejected", s.rejected}};
}

/// "5 hits, 0 misses in ~/.cache/sluice" or "off (why)".
std::string describeProgramCache(const gpu::ProgramCache& cache) {
    if (!cache.enabled())
        return "off (" + cache.offReason() + ")";
    const gpu::ProgramCacheStats& s = cache.stats();
    std::string text = plural(s.hits, "hit") + ", " + plural(s.misses, "miss", "misses");
    if (s.rejected > 0)
        text += ", " + std::to_string(s.rejected) + " rejected";
    return text + " in " + cache.dir().string();
}

void printJson(const BakeArgs& args, const BakeJob& job) {
    const glm::dvec3 size = job.meshBox.hi - job.meshBox.lo;
    nlohmann::ordered_json out = {{"output", args.output},
                                  {"mesh", args.mesh},
                                  {"bytes", job.bytes},
                                  {"meshBoxSize", {size.x, size.y, size.z}},
                                  {"importSeconds", job.importSeconds},
                                  {"bakeSeconds", job.bakeSeconds},
                                  {"pointsPerSecond", pointsPerSecond(job)},
                                  {"asset", toJson(job.asset->meta)}};
    if (job.asset->sparse())
        out["sparse"] = sparseJson(job);
    if (args.profile)
        out["profile"] = phasesJson(job.phases);
    if (job.backend == Backend::Gpu) {
        const GpuBakeStats& gpu = job.gpuStats;
        out["gpu"] = {{"renderer", job.renderer},
                      {"triangles", gpu.triangles},
                      {"bvhNodes", gpu.nodes},
                      {"bvhDepth", gpu.depth},
                      {"bvhSeconds", gpu.bvhSeconds},
                      {"dispatches", gpu.dispatches},
                      {"gpuBytes", gpu.gpuBytes},
                      {"windingPoints", gpu.pendingPoints},
                      {"exactWindingPoints", gpu.verifiedPoints}};
        out["gpu"]["programCache"] = programCacheJson(*job.programCache);
        if (args.profile) {
            out["gpu"]["distanceSeconds"] = gpu.distanceNs * 1e-9;
            out["gpu"]["signSeconds"] = gpu.signNs * 1e-9;
        }
    }
    std::cout << out.dump(2) << '\n';
}

void printSummary(const BakeArgs& args, const BakeJob& job) {
    const format::ColliderMeta& meta = job.asset->meta;
    const glm::dvec3 size = job.meshBox.hi - job.meshBox.lo;
    std::cout << "baked " << args.mesh << " -> " << args.output << " (" << job.bytes << " bytes)\n"
              << "  mesh box " << num(size.x) << " x " << num(size.y) << " x " << num(size.z)
              << " world units\n"
              << "  grid     " << describeDims(meta.dims) << ", voxel size " << num(meta.voxelSize)
              << " world units\n"
              << "  origin   (" << num(meta.origin.x) << ", " << num(meta.origin.y) << ", "
              << num(meta.origin.z) << ") world units\n"
              << "  sign     " << signMethodName(meta.bake.signUsed) << " (requested "
              << meta.bake.signMode << ")\n"
              << "  mesh     " << describeMesh(meta.mesh) << '\n'
              << "  storage  " << storageName(meta.storage);
    if (meta.storage == format::Storage::F16)
        std::cout << ", quantization error " << num(meta.quantizationError, 3) << " world units ("
                  << num(meta.quantizationError / meta.voxelSize, 3) << " voxels)";
    std::cout << "\n  time     import " << num(job.importSeconds, 3) << " s, bake "
              << num(job.bakeSeconds, 3) << " s (" << num(pointsPerSecond(job), 3)
              << " voxels/s)\n";
    if (meta.layout == format::Layout::Sparse) {
        const SparseBakeStats& s = job.sparseStats;
        std::cout << "  sparse   band " << num(meta.bandWidth)
                  << " voxels: " << plural(s.bricks, "brick") << " (" << s.voxelsComputed
                  << " exact distances), " << plural(s.uniformBlocks, "uniform block") << ", "
                  << s.activeVoxels << " active voxels, grid " << s.gridBytes << " bytes\n"
                  << "           cull " << num(s.planSeconds, 3) << " s (" << s.distanceQueries
                  << " queries), distances " << num(s.distanceSeconds, 3) << " s, build "
                  << num(s.buildSeconds, 3) << " s, peak memory "
                  << num(double(peakRssBytes()) / (1 << 20), 4) << " MiB\n";
    }
    if (job.backend == Backend::Gpu) {
        const GpuBakeStats& gpu = job.gpuStats;
        std::cout << "  gpu      " << job.renderer << ", BVH of " << plural(gpu.nodes, "node")
                  << " (depth " << gpu.depth << ") in " << num(gpu.bvhSeconds, 3) << " s, "
                  << plural(gpu.dispatches, "dispatch", "dispatches") << '\n'
                  << "  programs " << describeProgramCache(*job.programCache) << '\n';
        if (args.profile)
            std::cout << "  passes   distance " << num(gpu.distanceNs * 1e-6, 4) << " ms, sign "
                      << num(gpu.signNs * 1e-6, 4) << " ms (GPU time); winding number at "
                      << plural(gpu.pendingPoints, "grid point") << ", exact at "
                      << gpu.verifiedPoints << "\n";
    }
    if (args.profile)
        std::cout << describePhases(job.phases);
}

} // namespace

int runBake(const BakeArgs& args) {
    BakeJob job;
    if (const int code = checkArguments(args, job); code != kExitOk)
        return code;
    if (const int code = importAndPlan(args, job); code != kExitOk)
        return code;
    if (const int code = openBackend(args, job); code != kExitOk)
        return code;
    if (const int code = bakeField(args, job); code != kExitOk)
        return code;
    if (const int code = writeOutput(args, job); code != kExitOk)
        return code;
    if (args.json)
        printJson(args, job);
    else if (!args.quiet)
        printSummary(args, job);
    return kExitOk;
}

Command addBakeCommand(CLI::App& parent) {
    return addSubcommand(
        parent, "bake",
        "Bake a mesh (any format assimp reads, or a level-set .vdb) into a collider "
        "asset (.slc). OUT is written only after a successful bake, atomically.",
        addBakeOptions, runBake);
}

} // namespace sluice::bake::cli
