// One batch-manifest entry as a library call: the manifest's entries, freshness, and the bake.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sluice/bake/jobs/BakeJob.h"
#include "sluice/bake/jobs/Progress.h"
#include "sluice/format/scene/BatchManifest.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// One collider of a batch manifest (`sluice-bake batch`), paths resolved against the
/// manifest's folder.
struct BatchEntry {
    std::string mesh;    ///< mesh file
    std::string output;  ///< asset file to write
    std::string label;   ///< "output" as the manifest spells it
    BakeRequest request; ///< the entry's bake options (defaults of `bake`)
};

/// What became of one entry.
struct BatchEntryResult {
    bool fresh = false;             ///< the output was up to date: nothing was baked
    double seconds = 0.0;           ///< [s] freshness check and bake
    std::uint64_t points = 0;       ///< [grid points] of the asset
    std::optional<double> maxError; ///< [voxels] recorded by `validate --write`, if any
};

/// The entry to bake for one collider of a manifest read by format::readBatchManifest.
BatchEntry batchEntryFor(const format::BatchEntry& collider);

/// The entries of a batch manifest (format/BatchManifest.h), checked whole by
/// format::readBatchManifest, whose errors it returns: each names the manifest and the JSON
/// path.
Result<std::vector<BatchEntry>> readBatchEntries(const std::filesystem::path& manifest);

/// The output of `entry` if it is fresh: a valid asset recording the XXH3 hash of the mesh
/// file's current bytes, the same settings and this tool version (`auto` accepts either
/// backend). Nothing if it is stale, missing or unreadable.
std::optional<format::ColliderAsset> freshBatchOutput(const BatchEntry& entry);

/// Bakes `entry` unless its output is fresh (or `force`), writing the output atomically as
/// `sluice-bake bake` does: the same bytes. A failure leaves the previous output as it was.
/// Errors: those of loadMeshFile, bakeMesh, encodeBaked and writeFileAtomic; the message says
/// what failed ("cannot read mesh 'rock.obj': ...").
Result<BatchEntryResult> bakeBatchEntry(const BatchEntry& entry, bool force,
                                        Progress* progress = nullptr);

} // namespace sluice::bake
