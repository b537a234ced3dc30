// One bake as a library call: what `sluice-bake bake` does between parsing and printing.
#include "sluice/bake/jobs/BakeJob.h"

#include <cmath>
#include <cstring>
#include <optional>

#include "commands/CliSupport.h"
#include "sluice/bake/Grid.h"
#include "sluice/bake/cgal/CgalBaker.h"
#include "sluice/bake/cgal/CgalSparseBaker.h"
#include "sluice/bake/gpu/GpuSparseBaker.h"
#include "sluice/bake/sparse/SparseBaker.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/support/Hash.h"
#include "sluice/gpu/Context.h"
#include "sluice/gpu/colliders/VolumeMap.h"

namespace sluice::bake {
namespace {

/// The most triangles an import accepts (MeshImport.cpp's limit), for arrays too.
constexpr std::uint64_t kMaxArrayTriangles = 20'000'000;

Result<format::Storage> parseStorage(const std::string& text) {
    if (text == "f32")
        return format::Storage::F32;
    if (text == "f16")
        return format::Storage::F16;
    return fail(ErrorCode::InvalidArgument, "--storage " + text + ": expected f32 or f16");
}

Result<void> checkBackend(const std::string& text) {
    if (text == "auto" || text == "gpu" || text == "cgal")
        return {};
    return fail(ErrorCode::InvalidArgument,
                "--backend " + text + ": unknown backend (available: auto, gpu, cgal)");
}

} // namespace

Result<BakeSettings> bakeSettingsFor(const BakeRequest& request) {
    if (Result<void> backend = checkBackend(request.backend); !backend)
        return backend.error();
    Result<SignMode> sign = parseSignMode(request.sign);
    if (!sign)
        return fail(ErrorCode::InvalidArgument,
                    "--sign " + request.sign + ": " + sign.error().detail);
    Result<format::Storage> storage = parseStorage(request.storage);
    if (!storage)
        return storage.error();
    if (!std::isfinite(request.scale) || request.scale <= 0.0)
        return fail(ErrorCode::InvalidArgument, "--scale: expected a finite number > 0");
    if (!std::isfinite(request.padding) || request.padding < 0.0)
        return fail(ErrorCode::InvalidArgument, "--padding: expected a finite number >= 0");
    if (request.voxelSize != 0.0 && !(std::isfinite(request.voxelSize) && request.voxelSize > 0))
        return fail(ErrorCode::InvalidArgument, "--voxel-size: expected a finite number > 0");
    if (request.voxelSize <= 0.0 && (request.resolution < 1 || request.resolution > 4096))
        return fail(ErrorCode::InvalidArgument, "--resolution " +
                                                    std::to_string(request.resolution) +
                                                    ": not in range [1 - 4096]");
    BakeSettings settings;
    settings.grid.resolution = request.voxelSize > 0.0 ? 0 : request.resolution;
    settings.grid.voxelSize = request.voxelSize;
    settings.grid.padding = request.padding;
    settings.sign = *sign;
    settings.storage = *storage;
    settings.scale = request.scale;
    return settings;
}

Result<ImportedMesh> loadMeshFile(const std::filesystem::path& path, double scale) {
    return cli::loadMesh(path, scale);
}

Result<format::ColliderAsset> loadAssetFile(const std::filesystem::path& path) {
    return cli::loadAsset(path);
}

Result<ImportedMesh> meshFromArrays(std::span<const glm::dvec3> positions,
                                    std::span<const glm::uvec3> triangles,
                                    const std::string& name) {
    if (triangles.empty())
        return fail(ErrorCode::EmptyMesh, name + ": no triangles");
    if (triangles.size() > kMaxArrayTriangles || positions.size() > 0xffffffffu)
        return fail(ErrorCode::SizeOverflow, name + ": more than " +
                                                 std::to_string(kMaxArrayTriangles) +
                                                 " triangles or 2^32 vertices");
    for (std::size_t v = 0; v < positions.size(); ++v) {
        const glm::dvec3& p = positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return fail(ErrorCode::NonFinite,
                        name + ": vertex " + std::to_string(v) + " is not finite");
    }
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3& tri = triangles[t];
        if (tri.x >= positions.size() || tri.y >= positions.size() || tri.z >= positions.size())
            return fail(ErrorCode::InvalidArgument,
                        name + ": triangle " + std::to_string(t) + " indexes a vertex past the " +
                            std::to_string(positions.size()) + " given");
    }
    ImportedMesh mesh;
    mesh.soup.positions.assign(positions.begin(), positions.end());
    mesh.soup.triangles.assign(triangles.begin(), triangles.end());
    mesh.diagnostics = diagnose(mesh.soup);
    mesh.sourceFile = name;
    std::vector<std::byte> bytes(positions.size_bytes() + triangles.size_bytes());
    std::memcpy(bytes.data(), positions.data(), positions.size_bytes());
    std::memcpy(bytes.data() + positions.size_bytes(), triangles.data(), triangles.size_bytes());
    mesh.sourceHash = format::hex64(format::xxh3(bytes));
    return mesh;
}

Result<double> requestBand(const BakeRequest& request, const Box& bounds, const GridOptions& grid) {
    if (request.sparse && request.forSpacing > 0.0)
        return bandForSpacing(bounds, grid, request.forSpacing, request.forKernelRadius);
    return request.band;
}

Result<BakeOutcome> bakeMesh(const ImportedMesh& mesh, const BakeRequest& request,
                             Progress* progress) {
    Result<BakeSettings> settings = bakeSettingsFor(request);
    if (!settings)
        return settings.error();
    if (request.sparse && settings->storage != format::Storage::F32)
        return fail(ErrorCode::InvalidArgument, "sparse assets store f32 values");
    // As `bake`: the grid is checked before a context opens.
    const Result<double> band = requestBand(request, mesh.soup.bounds(), settings->grid);
    if (!band)
        return band.error();
    Result<GridSpec> grid = request.sparse
                                ? sparseGridFor(mesh.soup.bounds(), settings->grid, *band)
                                : gridFor(mesh.soup.bounds(), settings->grid);
    if (!grid)
        return grid.error();

    BakeOutcome outcome;
    std::optional<Result<gpu::Context>> context;
    bool gpu = request.backend != "cgal";
    if (gpu) {
        context.emplace(gpu::Context::createHeadless());
        if (!*context && request.backend == "gpu")
            return context->error();
        if (!*context) {
            outcome.fallback = context->error().detail;
            gpu = false;
        }
    }
    std::optional<Result<format::ColliderAsset>> asset;
    const SparseSettings sparse{.band = *band};
    if (gpu) {
        outcome.backend = "gpu";
        outcome.renderer = (*context)->info().renderer;
        gpu::ProgramCache cache = gpu::ProgramCache::open();
        const GpuBakeOptions options{.programCache = &cache};
        asset.emplace(request.sparse ? bakeSparseGpu(mesh, *settings, sparse, **context, false,
                                                     options, &outcome.gpuStats)
                                     : bakeGpu(mesh, *settings, **context, progress, options,
                                               &outcome.gpuStats));
    } else {
        outcome.backend = "cgal";
        asset.emplace(request.sparse ? bakeSparseCgal(mesh, *settings, sparse)
                                     : bakeCgal(mesh, *settings, progress));
    }
    if (!*asset)
        return asset->error();
    outcome.asset = std::move(asset->value());
    if (auto maps = bakeVolumeMaps(outcome.asset, request.volumeMaps, gpu); !maps)
        return maps.error();
    return outcome;
}

Result<std::vector<std::byte>> encodeBaked(format::ColliderAsset& asset) {
    Result<format::EncodedAsset> encoded = format::encodeAsset(asset);
    if (!encoded)
        return encoded.error();
    asset.meta.quantizationError = encoded->quantizationError;
    return std::move(encoded->bytes);
}

Result<void> checkVolumeMapSupports(const std::vector<double>& supports) {
    if (supports.size() > format::kMaxVolumeMaps)
        return fail(ErrorCode::InvalidArgument, std::to_string(supports.size()) +
                                                    " volume maps asked for; at most " +
                                                    std::to_string(format::kMaxVolumeMaps));
    for (std::size_t m = 0; m < supports.size(); ++m) {
        if (!std::isfinite(supports[m]) || !(supports[m] > 0.0))
            return fail(ErrorCode::InvalidArgument, "volume map support " +
                                                        std::to_string(supports[m]) +
                                                        " is not a number > 0");
        for (std::size_t o = 0; o < m; ++o)
            if (std::abs(supports[o] - supports[m]) <=
                format::kVolumeMapSupportTolerance * supports[m])
                return fail(ErrorCode::InvalidArgument, "volume map support " +
                                                            std::to_string(supports[m]) +
                                                            " is given twice");
    }
    return {};
}

Result<void> bakeVolumeMaps(format::ColliderAsset& asset, const std::vector<double>& supports,
                            bool contextCurrent) {
    if (supports.empty())
        return {};
    if (auto ok = checkVolumeMapSupports(supports); !ok)
        return ok;
    std::optional<Result<gpu::Context>> own;
    if (!contextCurrent) {
        own.emplace(gpu::Context::createHeadless());
        if (!*own)
            return fail(own->error().code,
                        "volume maps are computed with OpenGL 4.5 compute shaders: " +
                            own->error().detail);
    }
    for (double support : supports) {
        auto values = gpu::computeVolumeMap(asset, support);
        if (!values)
            return values.error();
        asset.volumeMaps.push_back({support, std::move(*values)});
    }
    return {};
}

std::string colliderMetaJson(const format::ColliderMeta& meta) {
    return cli::toJson(meta).dump();
}

std::string meshDiagnosticsJson(const format::MeshDiagnostics& mesh) {
    return cli::toJson(mesh).dump();
}

std::string bakeToolVersion() {
    return cli::toolVersion();
}

} // namespace sluice::bake
