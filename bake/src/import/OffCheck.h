// A pre-flight check of an OFF file (header and body) before assimp reads it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "sluice/format/support/Result.h"

namespace sluice::bake::detail {

/// Checks the OFF file `path` of `fileBytes` against its header before assimp reads it; a
/// MeshImport error that starts with `shown` and names the line.
///
/// First the declared counts: assimp allocates for them before reading (a 12-line OFF file
/// asking for 353 billion vertices takes all memory), so they must fit in the file, each
/// vertex needing at least 6 bytes ("0 0 0\n") and each face 8 ("3 0 1 2\n"). Then the body:
/// the vertex lines (three numbers each, and whatever colour or normal follows) and every face
/// line, whose corner count must be followed on the same line by that many vertex indices, each
/// below the vertex count. Debian's assimp 5.2.5 reads a face's corners past the end of its
/// buffer when the file does not hold them (a SEGV; found by tests/fuzz, and contained by the
/// isolated import, but a user deserves the line number). Files with the header's counts on
/// the first line or glued to the magic ("OFF8 6 0"), and '#' comments, are read as assimp
/// does; binary OFF is left to assimp.
Result<void> checkOffFile(const std::filesystem::path& path, std::uintmax_t fileBytes,
                          const std::string& shown);

} // namespace sluice::bake::detail
