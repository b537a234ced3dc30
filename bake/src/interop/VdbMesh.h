// Private: OpenVDB level sets to meshes and back, shared by the .vdb and .nvdb paths.
#pragma once

#include <filesystem>
#include <string>

#include "interop/VdbHeaders.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake::detail {

/// "'path'": how the .vdb and .nvdb messages name a file.
inline std::string quoted(const std::filesystem::path& path) {
    return "'" + path.string() + "'";
}

/// The zero isosurface of `grid` as a welded, outward-oriented soup scaled by `scale`, with
/// diagnostics and the hash of `path` (the file it came from). Errors as importVdbLevelSet.
Result<ImportedMesh> meshLevelSet(const openvdb::FloatGrid& grid, const std::filesystem::path& path,
                                  double scale);

/// A sparse asset's NanoVDB grid as an OpenVDB level set (nanoToOpenVDB), named "sdf".
/// Precondition: asset.sparse() and its grid passed checkNanoVdbGrid.
openvdb::FloatGrid::Ptr sparseToOpenVdb(const format::ColliderAsset& asset);

} // namespace sluice::bake::detail
