// Private: the one atomic .vdb writer, shared by `export` and `surface`.
#pragma once

#include <filesystem>

#include "interop/VdbHeaders.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake::detail {

/// Writes `grids` into one .vdb file at `path` atomically: a temporary file in the same folder,
/// checked on disk (checkVdbExtents: OpenVDB does not report short writes) and fsync'd, then
/// renamed over `path`. On any failure the temporary file is removed, `path` is left as it was,
/// and Io is returned naming `path` (folder missing, `path` a folder, OpenVDB failure, disk
/// full, rename failure).
Result<void> writeVdbAtomically(const openvdb::GridCPtrVec& grids,
                                const std::filesystem::path& path);

} // namespace sluice::bake::detail
