// OpenVDB interchange: collider assets out as float level sets, level sets in as meshes.
#pragma once

#include <filesystem>

#include "sluice/bake/import/MeshImport.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// Writes a FloatGrid of class level set named "sdf", with a linear transform mapping index
/// (i, j, k) to origin + (i, j, k) * voxelSize, every grid point stored as an active voxel,
/// background set to the largest |phi|. A sparse asset is written as its narrow band instead
/// (nanoToOpenVDB: band voxels active, signed tiles, background +band). Provenance goes into grid
/// metadata (string values "sluice_source_file", "sluice_source_hash", "sluice_tool_version",
/// "sluice_bake_backend", "sluice_sign_method", "sluice_exported_by"; the creator is the asset's
/// tool version). Written atomically (temp file in the same folder + rename). Errors:
/// InvalidArgument (distances.size() != pointCount(), empty grid, bad voxel size), NonFinite,
/// SizeOverflow, Io (folder missing, OpenVDB write failure, rename failure; nothing is left
/// behind).
Result<void> exportVdb(const format::ColliderAsset& asset, const std::filesystem::path& path);

/// Reads the first float level-set grid of a .vdb file (else the first float grid, with a
/// warning on stderr) and extracts its zero isosurface as a triangle soup in world units
/// (openvdb::tools::volumeToMesh, isovalue 0, adaptivity 0, quads split in two, welded,
/// oriented outward), scaled by `scale`, so it bakes like any mesh. Diagnostics and source
/// hash are filled as for importMesh. Errors: Io (missing, unreadable), MeshImport (not a VDB,
/// corrupt), Truncated (the file ends early), Unsupported (no float grid at all, e.g. only
/// Vec3 grids), EmptyMesh (no active voxels or no zero crossing), InvalidArgument (bad scale).
Result<ImportedMesh> importVdbLevelSet(const std::filesystem::path& path, double scale = 1.0);

/// Reads the first float grid (level sets first, as importVdbLevelSet) back as a dense collider
/// asset over its active bounding box: bit-exact distances, origin and voxel size for files
/// written by exportVdb, whose provenance metadata it restores; other files record themselves
/// as the source (backend "vdb", sign Level). Used by the round-trip test and `info` on .vdb.
/// Errors as importVdbLevelSet, plus Unsupported (rotated, non-uniform or frustum transform,
/// or fewer than 2 voxels along an axis), SizeOverflow (over kMaxGridPoints), NonFinite.
Result<format::ColliderAsset> readVdbDense(const std::filesystem::path& path);

} // namespace sluice::bake
