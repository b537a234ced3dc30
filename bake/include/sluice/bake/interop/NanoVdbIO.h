// NanoVDB interchange: sparse collider grids out as .nvdb files, .nvdb level sets in.
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include "sluice/bake/import/MeshImport.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/asset/NanoVdbCheck.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// [bytes] largest .nvdb file read: one grid at the format's limit plus its file headers.
inline constexpr std::uint64_t kMaxNvdbFileBytes = format::kMaxNanoVdbBytes + (1u << 20);

/// The bytes of a .nvdb file holding `grid` (one uncompressed segment: NanoVDB's file header,
/// the grid's metadata and name, then the grid), as nanovdb::io::writeGrid lays them out.
/// Precondition: `grid` passed checkNanoVdbGrid. Errors: Unsupported if NanoVDB throws.
Result<std::vector<std::byte>> encodeNvdb(const format::GridBytes& grid);

/// Writes a sparse asset's grid as a .nvdb file, atomically. Errors: InvalidArgument for a
/// dense asset (bake it with --sparse), as encodeNvdb, and Io.
Result<void> exportNvdb(const format::ColliderAsset& asset, const std::filesystem::path& path);

/// Reads the first grid of a .nvdb file, treating the file as hostile: the file header, each
/// grid's metadata and name length are bounds-checked, the codec must be NONE (Unsupported
/// otherwise), and the grid must pass checkNanoVdbGrid (its codes). Io if it cannot be read,
/// SizeOverflow over kMaxNvdbFileBytes.
Result<format::GridBytes> readNvdbGrid(const std::filesystem::path& path);

/// A .nvdb level set as a mesh to bake: its zero isosurface, as importVdbLevelSet does for .vdb
/// (the grid is converted with nanoToOpenVDB first). Errors as readNvdbGrid and
/// importVdbLevelSet.
Result<ImportedMesh> importNvdbLevelSet(const std::filesystem::path& path, double scale = 1.0);

} // namespace sluice::bake
