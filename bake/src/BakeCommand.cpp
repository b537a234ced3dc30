// `sluice-bake bake`: mesh (or level-set .vdb) in, collider asset out, with a short summary.
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>

#include "CliSupport.h"
#include "sluice/bake/CgalReference.h"
#include "sluice/bake/Cli.h"
#include "sluice/bake/GpuBaker.h"
#include "sluice/bake/Grid.h"
#include "sluice/format/AssetIO.h"
#include "sluice/format/AtomicFile.h"
#include "sluice/gpu/Context.h"

namespace sluice::bake::cli {
namespace {

/// Where the distances are computed: the GPU baker, the exact CPU reference, or (the default)
/// the GPU where a GL 4.5 context opens and the CPU reference otherwise. Both give the same
/// exact field; the asset records the one that ran.
enum class Backend { Auto, Gpu, Cgal };

Result<Backend> parseBackend(const std::string& text) {
    if (text == "auto")
        return Backend::Auto;
    if (text == "cgal")
        return Backend::Cgal;
    if (text == "gpu")
        return Backend::Gpu;
    return fail(ErrorCode::InvalidArgument,
                "--backend " + text + ": unknown backend (available: auto, gpu, cgal)");
}

Result<format::Storage> parseStorage(const std::string& text) {
    if (text == "f32")
        return format::Storage::F32;
    if (text == "f16")
        return format::Storage::F16;
    return fail(ErrorCode::InvalidArgument, "--storage " + text + ": expected f32 or f16");
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

int runBake(const BakeArgs& args) {
    constexpr std::string_view cmd = "bake";
    // Every argument is checked before the mesh is read, so mistakes fail fast.
    Result<Backend> backend = parseBackend(args.backend);
    if (!backend)
        return reportBadInput(cmd, backend.error().detail);
    Result<SignMode> sign = parseSignMode(args.sign);
    if (!sign)
        return reportBadInput(cmd, "--sign " + args.sign + ": " + sign.error().detail);
    Result<format::Storage> storage = parseStorage(args.storage);
    if (!storage)
        return reportBadInput(cmd, storage.error().detail);
    if (Result<void> out = checkOutputPath(args.output); !out)
        return reportFileError(cmd, "cannot write", args.output, out.error());

    BakeSettings settings;
    settings.grid.resolution = args.voxelSize > 0.0 ? 0 : args.resolution;
    settings.grid.voxelSize = args.voxelSize;
    settings.grid.padding = args.padding;
    settings.sign = *sign;
    settings.storage = *storage;
    settings.scale = args.scale;

    const auto importStart = std::chrono::steady_clock::now();
    Result<ImportedMesh> mesh = loadMesh(args.mesh, args.scale);
    if (!mesh)
        return reportFileError(cmd, "cannot read mesh", args.mesh, mesh.error());
    const double importSeconds = secondsSince(importStart);

    Result<GridSpec> grid = gridFor(mesh->soup.bounds(), settings.grid);
    if (!grid)
        return reportFileError(cmd, "cannot bake", args.mesh, grid.error());

    const auto bakeStart = std::chrono::steady_clock::now();
    std::optional<Result<format::ColliderAsset>> asset;
    GpuBakeStats gpuStats;
    std::string renderer;
    std::optional<Result<gpu::Context>> context;
    if (*backend != Backend::Cgal) {
        context.emplace(gpu::Context::createHeadless());
        if (!*context && *backend == Backend::Gpu)
            return reportError(cmd, "no GPU context for --backend gpu (use --backend cgal)",
                               context->error());
        if (!*context) {
            // auto: the same exact field from the CPU reference, only slower.
            std::cerr << "sluice-bake bake: no OpenGL 4.5 context (" << context->error().detail
                      << "); baking on the CPU with the CGAL backend\n";
            backend = Backend::Cgal;
        } else {
            backend = Backend::Gpu;
        }
    }
    switch (*backend) {
    case Backend::Auto: break; // resolved above
    case Backend::Gpu: {
        renderer = (*context)->info().renderer;
        Progress progress("baking " + mesh->sourceFile + " on the GPU", grid->pointCount(),
                          !args.quiet);
        asset.emplace(
            bakeGpu(*mesh, settings, **context, &progress, {.profile = args.profile}, &gpuStats));
        progress.finish();
        break;
    }
    case Backend::Cgal: {
        Progress progress("baking " + mesh->sourceFile, grid->pointCount(), !args.quiet);
        asset.emplace(bakeCgal(*mesh, settings, &progress));
        progress.finish();
        break;
    }
    }
    if (!asset->ok())
        return reportFileError(cmd, "cannot bake", args.mesh, asset->error());
    const double bakeSeconds = secondsSince(bakeStart);
    format::ColliderAsset& result = asset->value();

    // Encode first and write atomically after: a failed bake or encode leaves OUT untouched.
    Result<format::EncodedAsset> encoded = format::encodeAsset(result);
    if (!encoded)
        return reportFileError(cmd, "cannot encode the asset for", args.output, encoded.error());
    result.meta.quantizationError = encoded->quantizationError;
    if (Result<void> written = format::writeFileAtomic(args.output, encoded->bytes); !written)
        return reportFileError(cmd, "cannot write", args.output, written.error());

    const format::ColliderMeta& meta = result.meta;
    const double points = double(result.pointCount());
    const double rate = bakeSeconds > 0.0 ? points / bakeSeconds : 0.0;
    if (args.json) {
        nlohmann::ordered_json out = {
            {"output", args.output},          {"mesh", args.mesh},
            {"bytes", encoded->bytes.size()}, {"importSeconds", importSeconds},
            {"bakeSeconds", bakeSeconds},     {"pointsPerSecond", rate},
            {"asset", toJson(meta)}};
        if (*backend == Backend::Gpu) {
            out["gpu"] = {{"renderer", renderer},
                          {"triangles", gpuStats.triangles},
                          {"bvhNodes", gpuStats.nodes},
                          {"bvhDepth", gpuStats.depth},
                          {"bvhSeconds", gpuStats.bvhSeconds},
                          {"dispatches", gpuStats.dispatches},
                          {"gpuBytes", gpuStats.gpuBytes}};
            if (args.profile) {
                out["gpu"]["distanceSeconds"] = gpuStats.distanceNs * 1e-9;
                out["gpu"]["signSeconds"] = gpuStats.signNs * 1e-9;
            }
        }
        std::cout << out.dump(2) << '\n';
    } else if (!args.quiet) {
        std::cout << "baked " << args.mesh << " -> " << args.output << " (" << encoded->bytes.size()
                  << " bytes)\n"
                  << "  grid     " << describeDims(meta.dims) << ", voxel " << num(meta.voxelSize)
                  << " world units\n"
                  << "  origin   (" << num(meta.origin.x) << ", " << num(meta.origin.y) << ", "
                  << num(meta.origin.z) << ") world units\n"
                  << "  sign     " << signMethodName(meta.bake.signUsed) << " (requested "
                  << meta.bake.signMode << ")\n"
                  << "  mesh     " << describeMesh(meta.mesh) << '\n'
                  << "  storage  " << storageName(meta.storage);
        if (meta.storage == format::Storage::F16)
            std::cout << ", quantization error " << num(meta.quantizationError, 3)
                      << " world units (" << num(meta.quantizationError / meta.voxelSize, 3)
                      << " voxels)";
        std::cout << "\n  time     import " << num(importSeconds, 3) << " s, bake "
                  << num(bakeSeconds, 3) << " s (" << num(rate, 3) << " voxels/s)\n";
        if (*backend == Backend::Gpu) {
            std::cout << "  gpu      " << renderer << ", BVH of " << gpuStats.nodes
                      << " nodes (depth " << gpuStats.depth << ") in "
                      << num(gpuStats.bvhSeconds, 3) << " s, " << gpuStats.dispatches
                      << " dispatches\n";
            if (args.profile)
                std::cout << "  passes   distance " << num(gpuStats.distanceNs * 1e-6, 4)
                          << " ms, sign " << num(gpuStats.signNs * 1e-6, 4) << " ms (GPU time)\n";
        }
    }
    return kExitOk;
}

Command addBakeCommand(CLI::App& parent) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* app = parent.add_subcommand(
        "bake", "Bake a mesh (any format assimp reads, or a level-set .vdb) into a collider "
                "asset (.slc). OUT is written only after a successful bake, atomically.");
    app->add_option("MESH", args->mesh, "input mesh file")->required();
    app->add_option("-o,--output", args->output, "output asset file (.slc)")
        ->required()
        ->type_name("OUT");
    app->add_option("--backend", args->backend,
                    "where distances are computed: auto (gpu where an OpenGL 4.5 context opens, "
                    "otherwise cgal), gpu (OpenGL 4.5 compute, headless; exit 3 without a "
                    "context) or cgal (the exact CPU reference, all cores). All give the same "
                    "exact field")
        ->capture_default_str();
    CLI::Option* resolution =
        app->add_option("--resolution", args->resolution,
                        "[voxels] along the longest side of the mesh box, 1..4096")
            ->check(CLI::Range(1u, 4096u))
            ->capture_default_str();
    CLI::Option* voxelSize = app->add_option("--voxel-size", args->voxelSize,
                                             "[world units] grid spacing, instead of --resolution")
                                 ->check(finiteNumber(false));
    resolution->excludes(voxelSize);
    voxelSize->excludes(resolution);
    app->add_option("--padding", args->padding, "[voxels] margin on every side of the mesh box")
        ->check(finiteNumber(true))
        ->capture_default_str();
    app->add_option("--sign", args->sign,
                    "inside/outside method: auto (parity if closed and not self-intersecting, "
                    "else winding), parity, winding. On the GPU, parity is the winding number of "
                    "the consistently oriented closed mesh rounded, odd meaning inside (equal to "
                    "ray parity on a closed surface)")
        ->capture_default_str();
    app->add_option("--scale", args->scale, "uniform scale applied to the mesh at import")
        ->check(finiteNumber(false))
        ->capture_default_str();
    app->add_option("--storage", args->storage, "sample type in the file: f32 or f16")
        ->capture_default_str();
    app->add_flag("-q,--quiet", args->quiet, "no progress bar and no summary");
    app->add_flag("--json", args->json, "print the summary as JSON");
    app->add_flag("--profile", args->profile,
                  "gpu backend: time the GPU passes with timer queries and print them");
    return {app, [args] { return runBake(*args); }};
}

} // namespace sluice::bake::cli
