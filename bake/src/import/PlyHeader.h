// Private: the header of a PLY file as the pre-flight check reads it (PlyCheck.h says what is
// checked, and why).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sluice/format/support/Result.h"

namespace sluice::bake::detail {

/// [bytes] The header is read up to the first 1 MiB of the file.
inline constexpr std::size_t kMaxPlyHeaderBytes = std::size_t(1) << 20;

/// The scalar types of the format.
enum class PlyScalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

/// [bytes] of one value of type `s`.
std::size_t bytesOf(PlyScalar s);
/// Whether `s` is an integer type.
bool isInteger(PlyScalar s);
/// The inclusive range an integer type holds; +-infinity for the float types.
std::pair<double, double> rangeOf(PlyScalar s);

/// "property TYPE NAME" or "property list COUNTTYPE ITEMTYPE NAME".
struct PlyProperty {
    std::string name;
    bool list = false;
    PlyScalar count = PlyScalar::UInt8; // lists only
    PlyScalar value = PlyScalar::Float32;
};

/// "element NAME COUNT" and its properties.
struct PlyElement {
    std::string name;
    std::uint64_t count = 0; ///< instances (below 2^32 once the header is accepted)
    double declared = 0.0;   ///< the count as the header writes it, however large
    std::vector<PlyProperty> properties;
    /// The list of vertex indices, for "face" and "tristrips"; -1 when there is none.
    int indexList = -1;
    /// Triangle strips, whose index lists may hold -1 (a strip break).
    bool strips() const { return name == "tristrips"; }
};

enum class PlyEncoding { Ascii, LittleEndian, BigEndian };

/// A "comment" line of the header: what follows the keyword, and where.
struct PlyComment {
    std::size_t line = 0; ///< the line's number, from 1
    std::string text;     ///< the words after "comment", joined by one space
};

/// What an accepted header declares.
struct PlyHeader {
    PlyEncoding encoding = PlyEncoding::Ascii;
    std::vector<PlyElement> elements;
    std::uint64_t bodyOffset = 0;     ///< [bytes] where the body starts
    std::size_t bodyFirstLine = 0;    ///< the number of the body's first line, from 1
    std::uint64_t vertexCount = 0;    ///< of the "vertex" element
    std::vector<PlyComment> comments; ///< in the order of the header
};

/// What a header must declare to be accepted: a mesh (vertex positions and faces, what
/// `bake` reads) or points (vertex positions only, what `surface` reads).
enum class PlyContent { Mesh, Points };

/// Reads the header from `head` (the first bytes of a file of `fileBytes`, up to
/// kMaxPlyHeaderBytes, starting with the magic), checks it, and checks that it declares
/// `content`. Errors: MeshImport naming `shown` and the line, EmptyMesh without faces (Mesh).
Result<PlyHeader> readPlyHeader(const std::string& head, std::uint64_t fileBytes,
                                const std::string& shown, PlyContent content = PlyContent::Mesh);

/// The MeshImport error "<shown>: line <line>: <what>".
Error plyProblem(const std::string& shown, std::size_t line, const std::string& what);
/// The MeshImport error "<shown>: <what>", for what has no line.
Error plyProblem(const std::string& shown, const std::string& what);

} // namespace sluice::bake::detail
