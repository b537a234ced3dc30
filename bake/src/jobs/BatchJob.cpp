// One batch-manifest entry as a library call: the manifest's entries, freshness, and the bake.
#include "sluice/bake/jobs/BatchJob.h"

#include <algorithm>
#include <chrono>

#include "commands/CliSupport.h"
#include "sluice/bake/jobs/PhaseLog.h"
#include "sluice/bake/sparse/SparseBaker.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/support/AtomicFile.h"
#include "sluice/format/support/Hash.h"

namespace sluice::bake {
namespace {

namespace fs = std::filesystem;

/// "<what> '<path>': <detail>", unless the detail already names the path (as the command
/// line's reportFileError words it).
Error named(const std::string& what, const std::string& path, const Error& error) {
    const bool shown = error.detail.find(path) != std::string::npos;
    return Error{error.code, (shown ? what : what + " '" + path + "'") + ": " + error.detail};
}

// Whether `asset` holds every volume map `supports` asks for. More are fine: a manifest that asks
// for none (the demo's, beside the build's that baked them) keeps an asset's maps.
bool holdsVolumeMaps(const format::ColliderAsset& asset, const std::vector<double>& supports) {
    return std::all_of(supports.begin(), supports.end(),
                       [&](double s) { return asset.volumeMapFor(s) != nullptr; });
}

} // namespace

BatchEntry batchEntryFor(const format::BatchEntry& collider) {
    BatchEntry entry;
    entry.mesh = collider.meshPath.string();
    entry.output = collider.outputPath.string();
    entry.label = collider.output;
    BakeRequest& r = entry.request;
    r.backend = collider.backend;
    r.resolution = collider.resolution;
    r.voxelSize = collider.voxelSize;
    r.padding = collider.padding;
    r.sign = collider.sign;
    r.storage = collider.storage;
    r.scale = collider.scale;
    r.sparse = collider.sparse;
    r.band = collider.band;
    r.forSpacing = collider.forSpacing;
    r.forKernelRadius = collider.forKernelRadius;
    r.volumeMaps = collider.volumeMaps;
    return entry;
}

Result<std::vector<BatchEntry>> readBatchEntries(const fs::path& manifest) {
    Result<format::BatchManifest> read = format::readBatchManifest(manifest);
    if (!read)
        return read.error();
    std::vector<BatchEntry> entries;
    for (const format::BatchEntry& collider : read->colliders)
        entries.push_back(batchEntryFor(collider));
    return entries;
}

std::optional<format::ColliderAsset> freshBatchOutput(const BatchEntry& entry) {
    std::error_code ec;
    if (!fs::is_regular_file(entry.output, ec))
        return std::nullopt;
    Result<std::string> hash = format::hashFileHex(entry.mesh);
    if (!hash)
        return std::nullopt; // the bake will say what is wrong with the mesh
    Result<format::ColliderAsset> asset = format::readAsset(entry.output);
    if (!asset)
        return std::nullopt;
    const BakeRequest& r = entry.request;
    const format::ColliderMeta& meta = asset->meta;
    const bool byVoxelSize = r.voxelSize > 0.0;
    // A band picked for a spacing depends on the voxel size: the asset's, if it is the one asked.
    const Result<double> band = r.forSpacing > 0.0
                                    ? bandForVoxel(meta.voxelSize, r.forSpacing, r.forKernelRadius)
                                    : Result<double>(r.band);
    if (!band)
        return std::nullopt;
    const double padding = r.sparse ? sparsePadding(r.padding, *band) : r.padding;
    const bool same =
        meta.sourceHash == *hash && meta.sourceFile == fs::path(entry.mesh).filename().string() &&
        meta.toolVersion == cli::toolVersion() &&
        // auto takes either backend: both compute the same exact field.
        (meta.bake.backend == r.backend ||
         (r.backend == "auto" && (meta.bake.backend == "gpu" || meta.bake.backend == "cgal"))) &&
        meta.bake.resolution == (byVoxelSize ? 0u : r.resolution) &&
        (!byVoxelSize || meta.voxelSize == r.voxelSize) && meta.bake.padding == padding &&
        meta.bake.signMode == r.sign && meta.bake.scale == r.scale &&
        format::storageName(meta.storage) == r.storage && asset->sparse() == r.sparse &&
        (!r.sparse || meta.bandWidth == *band) && holdsVolumeMaps(*asset, r.volumeMaps);
    if (!same)
        return std::nullopt;
    return std::move(*asset);
}

Result<BatchEntryResult> bakeBatchEntry(const BatchEntry& entry, bool force, Progress* progress) {
    const auto start = std::chrono::steady_clock::now();
    auto describe = [&](const format::ColliderAsset& asset, bool fresh) {
        BatchEntryResult result;
        result.fresh = fresh;
        result.points = asset.pointCount();
        if (asset.meta.validation.known)
            result.maxError = asset.meta.validation.maxError;
        result.seconds = secondsSince(start);
        return result;
    };
    if (!force)
        if (std::optional<format::ColliderAsset> fresh = freshBatchOutput(entry))
            return describe(*fresh, true);
    // As `bake`: arguments, the output's folder, the mesh, the bake, then one atomic write.
    if (Result<BakeSettings> settings = bakeSettingsFor(entry.request); !settings)
        return settings.error();
    if (Result<void> out = cli::prepareOutputPath(entry.output); !out)
        return named("cannot write", entry.output, out.error());
    Result<ImportedMesh> mesh = loadMeshFile(entry.mesh, entry.request.scale);
    if (!mesh)
        return named("cannot read mesh", entry.mesh, mesh.error());
    Result<BakeOutcome> baked = bakeMesh(*mesh, entry.request, progress);
    if (!baked)
        return named("cannot bake", entry.mesh, baked.error());
    Result<std::vector<std::byte>> bytes = encodeBaked(baked->asset);
    if (!bytes)
        return named("cannot encode the asset for", entry.output, bytes.error());
    if (Result<void> written = format::writeFileAtomic(entry.output, *bytes); !written)
        return named("cannot write", entry.output, written.error());
    return describe(baked->asset, false);
}

} // namespace sluice::bake
