// One bake as a library call: options as `sluice-bake bake` takes them, backend choice, encoding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/bake/Grid.h"
#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/gpu/GpuBaker.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/bake/jobs/Progress.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// The options of one bake, spelled as `sluice-bake bake` and batch manifests spell them.
struct BakeRequest {
    std::string backend = "auto";  ///< "auto" (gpu where GL 4.5 opens, else cgal) | "gpu" | "cgal"
    std::uint32_t resolution = 64; ///< [voxels] along the longest side; unused if voxelSize > 0
    double voxelSize = 0.0;        ///< [world units]
    double padding = 3.0;          ///< [voxels] added on every side
    std::string sign = "auto";     ///< "auto" | "parity" | "winding"
    std::string storage = "f32";   ///< "f32" | "f16"
    double scale = 1.0;            ///< recorded in the asset; the mesh is already scaled
    bool sparse = false;           ///< a narrow-band NanoVDB asset (CGAL backend)
    double band = 3.0;             ///< [voxels] sparse: the band's half-width, 1..64
    /// [world units] sparse: when > 0, the band is the one a scene of this particle spacing
    /// needs (bandForSpacing), instead of `band`.
    double forSpacing = 0.0;
    double forKernelRadius = 0.0; ///< [world units] with forSpacing: the kernel (0: default)
    /// Supports to bake volume maps for [asset units: a scene's kernel radius over the
    /// collider's placement scale], computed on the GPU (gpu::computeVolumeMap); at most
    /// format::kMaxVolumeMaps.
    std::vector<double> volumeMaps;
};

/// Whether `supports` may be baked as volume maps: at most format::kMaxVolumeMaps, each a number
/// > 0, no two within format::kVolumeMapSupportTolerance. InvalidArgument naming the support.
Result<void> checkVolumeMapSupports(const std::vector<double>& supports);

/// Bakes a volume map of `asset` for each of `supports` (gpu::computeVolumeMap, of the field as
/// the asset stores it) into asset.volumeMaps, in the current GL context when `contextCurrent`,
/// else in a headless one opened here. Errors: checkVolumeMapSupports', no GL 4.5 context (its
/// code, the message saying the maps need it), computeVolumeMap's.
Result<void> bakeVolumeMaps(format::ColliderAsset& asset, const std::vector<double>& supports,
                            bool contextCurrent);

/// The band [voxels] `request` bakes with over `bounds` on `grid`: `band`, or for a sparse
/// request with forSpacing the one bandForSpacing picks. Errors: bandForSpacing's.
Result<double> requestBand(const BakeRequest& request, const Box& bounds, const GridOptions& grid);

/// A finished bake: the asset (provenance filled in, quantizationError still 0 until encoded)
/// and how it was made.
struct BakeOutcome {
    format::ColliderAsset asset;
    std::string backend;  ///< "gpu" or "cgal": the one that ran
    std::string fallback; ///< why `auto` baked on the CPU (no GL context); empty otherwise
    std::string renderer; ///< GL_RENDERER of a GPU bake
    GpuBakeStats gpuStats;
};

/// The settings of `request`, each option checked with the message the command line gives
/// ("--backend x: unknown backend (available: auto, gpu, cgal)"). Error: InvalidArgument.
Result<BakeSettings> bakeSettingsFor(const BakeRequest& request);

/// A mesh file through assimp, or the zero isosurface of a level-set `.vdb`, at `scale`: what
/// `bake`, `validate` and `batch` read.
Result<ImportedMesh> loadMeshFile(const std::filesystem::path& path, double scale);

/// A collider asset file (.slc), or the first float grid of a `.vdb` read densely.
Result<format::ColliderAsset> loadAssetFile(const std::filesystem::path& path);

/// A mesh from arrays already in memory: `positions` [world units], `triangles` indexing them.
/// Diagnosed as an import is; `name` is the recorded source file, and the source hash is the
/// XXH3-64 of the position bytes followed by the index bytes. Errors: EmptyMesh (no triangle),
/// InvalidArgument (an index out of range), NonFinite (a NaN or infinite coordinate),
/// SizeOverflow (over 20 M triangles or 2^32 vertices).
Result<ImportedMesh> meshFromArrays(std::span<const glm::dvec3> positions,
                                    std::span<const glm::uvec3> triangles, const std::string& name);

/// Bakes `mesh` as `sluice-bake bake` does: the grid, then the GPU (a headless context made
/// here, current on the calling thread while it runs) or the CGAL reference, `auto` falling
/// back to CGAL where no context opens. Errors: those of bakeSettingsFor, gridFor, bakeGpu and
/// bakeCgal; NoGlContext for backend "gpu" without a context.
Result<BakeOutcome> bakeMesh(const ImportedMesh& mesh, const BakeRequest& request,
                             Progress* progress = nullptr);

/// The file bytes of `asset` (encodeAsset); sets asset.meta.quantizationError to the figure
/// stored in the file, so the asset in memory matches what a reader of the file sees.
Result<std::vector<std::byte>> encodeBaked(format::ColliderAsset& asset);

/// The asset metadata as JSON text, exactly the "asset" object of `sluice-bake bake --json`.
std::string colliderMetaJson(const format::ColliderMeta& meta);

/// The mesh diagnostics as JSON text (the "mesh" object of the metadata).
std::string meshDiagnosticsJson(const format::MeshDiagnostics& mesh);

/// "sluice-bake <version>", what assets record and --version prints.
std::string bakeToolVersion();

} // namespace sluice::bake
