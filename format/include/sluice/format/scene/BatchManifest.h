// Reading batch manifests (the JSON list of colliders `sluice-bake batch` bakes), strictly.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sluice/format/support/Result.h"

namespace sluice::format {

/// [bytes] largest manifest file readBatchManifest accepts (SizeOverflow beyond).
inline constexpr std::uint64_t kMaxBatchManifestBytes = std::uint64_t(16) << 20;

/// [voxels] the range of a manifest entry's "resolution", as `sluice-bake bake --resolution`.
inline constexpr std::uint32_t kMinBakeResolution = 1;
inline constexpr std::uint32_t kMaxBakeResolution = 4096;

/// One collider of a manifest: the bake it asks for, with the defaults of `sluice-bake bake`
/// for the fields it leaves out. Every value has been checked as the bake flags check theirs.
struct BatchEntry {
    std::string mesh;                 ///< "mesh" as written (relative to the manifest's folder)
    std::string output;               ///< "output" as written
    std::filesystem::path meshPath;   ///< mesh resolved against the manifest's folder
    std::filesystem::path outputPath; ///< output resolved against the manifest's folder
    std::uint32_t resolution = 64;    ///< [voxels] along the longest side, 1..4096
    double voxelSize = 0.0;           ///< [world units] > 0 when given; 0: use resolution
    double padding = 3.0;             ///< [voxels] finite, >= 0
    std::string sign = "auto";        ///< "auto" | "parity" | "winding"
    double scale = 1.0;               ///< finite, > 0
    std::string storage = "f32";      ///< "f32" | "f16"
    std::string backend = "auto";     ///< "auto" | "gpu" | "cgal"
    bool sparse = false;              ///< a narrow-band NanoVDB asset (`bake --sparse`)
    double band = 3.0;                ///< [voxels] sparse: the band's half-width, 1..64
    double forSpacing = 0.0;          ///< [world units] sparse: the band for this spacing (0: band)
    double forKernelRadius = 0.0;     ///< [world units] with forSpacing: the kernel (0: default)
    std::vector<double> volumeMaps;   ///< [asset units] supports of the volume maps to bake
};

/// A manifest: { "colliders": [ { "mesh": ..., "output": ..., optional fields }, ... ] }.
struct BatchManifest {
    std::filesystem::path path;        ///< the manifest file, as given
    std::vector<BatchEntry> colliders; ///< in manifest order
};

/// Reads and checks a batch manifest. Errors name the file and the JSON path, and say what is
/// wrong with the manifest's fields ("colliders.json: colliders[1].resolution: expected a
/// number, got the string \"40\""): Io (cannot read the file), SizeOverflow (over
/// kMaxBatchManifestBytes), BadMetadata (not JSON, an unknown key (the closest known key is
/// suggested), a duplicate key, a wrong type, a missing "mesh" or "output"), NonFinite (NaN or
/// infinity), InvalidArgument (a value out of range, an unknown sign, storage or backend, both
/// resolution and voxelSize, "band" or "forSpacing" without "sparse": true, both "band" and
/// "forSpacing", "forKernelRadius" without "forSpacing", "sparse" with f16 storage or the
/// gpu backend, or two entries writing the same output).
Result<BatchManifest> readBatchManifest(const std::filesystem::path& file);

/// readBatchManifest on text already in memory; `file` names the manifest in messages and is
/// what relative paths are resolved against (its folder). It need not exist.
Result<BatchManifest> parseBatchManifest(std::string_view json, const std::filesystem::path& file);

} // namespace sluice::format
