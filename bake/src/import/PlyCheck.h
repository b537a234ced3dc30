// A pre-flight walk over a PLY file (header and body) before assimp reads it.
//
// Debian's assimp 5.2.5 trusts a PLY file's header: a header that declares an element twice,
// a property with too few or too many words, or a body that does not hold what the header
// declares can make its loader write past its own buffers (a heap corruption found by
// tests/fuzz before this check existed). sluice-bake reads meshes in a child process, so
// such a file could never take the tool down, but the user deserves the line that is wrong,
// and the fuzzer a loader that is never handed a file it cannot read.
//
// What is checked (https://paulbourke.net/dataformats/ply/ is the format):
//   - the header: "ply", one "format ascii|binary_little_endian|binary_big_endian 1.0" line,
//     "element NAME COUNT" with a count below 2^32 and a name not declared before,
//     "property TYPE NAME" and "property list COUNTTYPE ITEMTYPE NAME" with known types, each
//     after an element; "comment" and "obj_info" lines, and any other line, are skipped, as
//     assimp skips them (Blender 2.47 wrote a bare "Created by ..." line);
//   - the body, element by element: ASCII holds one instance per line with one number per
//     scalar property and, per list, a count then that many numbers; binary holds the bytes
//     the header's types and the list counts add up to;
//   - the header has an "end_header" line within its first 1 MiB, alone on its line (assimp
//     finds the body by that line's end, and loops for ever without one);
//   - the declared "vertex" and "face" counts fit in the file's size (assimp allocates for
//     them before reading);
//   - there is something to bake: a "vertex" element with scalar x, y and z, and a "face" or
//     "tristrips" element of at least one instance with a vertex_indices (or vertex_index)
//     list; a point cloud is refused as EmptyMesh here, so assimp never reads it;
//   - the vertex indices of "face" and "tristrips" lists are integers below the vertex count
//     (tristrips may also hold -1, the strip break).
// Keywords are matched in lower case only, as assimp matches them, so a line it skips is
// skipped here too.
// Data after the last element is ignored, as assimp ignores it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "sluice/format/support/Result.h"

namespace sluice::bake::detail {

/// Checks `path` (a file assimp reads as PLY) and returns
/// a MeshImport error that starts with `shown` and names the line, element and problem. A file
/// that does not start with "ply" (in any case) is not judged here: success, and assimp says
/// what it is. Whatever follows "ply" on the first line is ignored, as assimp ignores it.
Result<void> checkPlyFile(const std::filesystem::path& path, const std::string& shown);

/// Whether `start` (the first bytes of a file) begins with "ply" in any case: what makes
/// assimp read a file of an extension it does not know as PLY.
bool hasPlyMagic(std::string_view start);

/// `text` with ASCII letters in lower case (keywords, file extensions).
std::string lowered(std::string_view text);

/// The message for a header (PLY or OFF) whose declared elements cannot fit in its file:
/// "the header declares V vertices and F faces, more than its N bytes can hold".
std::string declaresMoreThanTheFileHolds(double vertices, double faces, std::uint64_t fileBytes);

} // namespace sluice::bake::detail
