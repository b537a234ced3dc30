// The header of a PLY file for the pre-flight check: its lines, types and counts, and whether
// it declares something to bake (PlyCheck.h says what is checked, and why).
#include "import/PlyHeader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string_view>

#include "import/PlyCheck.h"

namespace sluice::bake::detail {

namespace {

/// The type names of the format, old and new spellings.
std::optional<PlyScalar> scalarNamed(std::string_view word) {
    static constexpr std::pair<std::string_view, PlyScalar> kNames[] = {
        {"char", PlyScalar::Int8},      {"int8", PlyScalar::Int8},
        {"uchar", PlyScalar::UInt8},    {"uint8", PlyScalar::UInt8},
        {"short", PlyScalar::Int16},    {"int16", PlyScalar::Int16},
        {"ushort", PlyScalar::UInt16},  {"uint16", PlyScalar::UInt16},
        {"int", PlyScalar::Int32},      {"int32", PlyScalar::Int32},
        {"uint", PlyScalar::UInt32},    {"uint32", PlyScalar::UInt32},
        {"float", PlyScalar::Float32},  {"float32", PlyScalar::Float32},
        {"double", PlyScalar::Float64}, {"float64", PlyScalar::Float64}};
    const std::string name = lowered(word);
    for (const auto& [known, scalar] : kNames)
        if (name == known)
            return scalar;
    return std::nullopt;
}

/// The words of a header line, split at white space.
std::vector<std::string_view> wordsOf(std::string_view line) {
    std::vector<std::string_view> words;
    std::size_t at = 0;
    while (at < line.size()) {
        while (at < line.size() && std::isspace(static_cast<unsigned char>(line[at])))
            ++at;
        std::size_t end = at;
        while (end < line.size() && !std::isspace(static_cast<unsigned char>(line[end])))
            ++end;
        if (end > at)
            words.push_back(line.substr(at, end - at));
        at = end;
    }
    return words;
}

/// Reads one header; every error goes through problem() (with the current line) or
/// problemNoLine(), which prefix the file.
class PlyHeaderReader {
public:
    PlyHeaderReader(std::uint64_t fileBytes, const std::string& shown, PlyContent content)
        : m_fileBytes(fileBytes), m_shown(shown), m_content(content) {}

    /// The header's lines, then whether there is something to bake.
    Result<PlyHeader> read(const std::string& head) {
        if (Result<void> r = readLines(head); !r)
            return r.error();
        if (Result<void> r = checkSomethingToBake(); !r)
            return r.error();
        return std::move(m_header);
    }

private:
    Error problem(const std::string& what) const { return plyProblem(m_shown, m_line, what); }
    Error problemNoLine(const std::string& what) const { return plyProblem(m_shown, what); }

    /// The header's lines up to end_header: one format, the elements and their properties.
    Result<void> readLines(const std::string& head) {
        std::size_t at = 0;
        bool sawFormat = false;
        m_line = 0;
        while (at < head.size()) {
            // A line ends at "\n", "\r\n" or a lone "\r".
            std::size_t end = at;
            while (end < head.size() && head[end] != '\n' && head[end] != '\r')
                ++end;
            std::size_t next = end;
            if (next < head.size() && head[next] == '\r')
                ++next;
            if (next < head.size() && head[next] == '\n')
                ++next;
            ++m_line;
            const std::vector<std::string_view> words =
                wordsOf(std::string_view(head).substr(at, end - at));
            at = next;
            if (m_line == 1 || words.empty()) // the first line holds the magic (checked)
                continue;
            // Keywords in lower case only, as assimp matches them: a line it would skip is
            // skipped here too, so both see the same elements.
            const std::string_view key = words[0];
            if (key == "end_header") {
                // assimp finds the body by the line end after it (found by tests/fuzz: a
                // vertical tab and binary bytes after end_header crashed its binary reader).
                if (words.size() != 1)
                    return problem("end_header must end its line");
                if (!sawFormat)
                    return problem("end_header before any \"format\" line");
                m_header.bodyOffset = at;
                m_header.bodyFirstLine = m_line + 1;
                return checkDeclaredCounts();
            }
            if (key == "format") {
                if (sawFormat)
                    return problem("a second \"format\" line");
                if (Result<void> r = readFormat(words); !r)
                    return r;
                sawFormat = true;
            } else if (key == "element") {
                if (Result<void> r = readElement(words); !r)
                    return r;
            } else if (key == "property") {
                if (Result<void> r = readProperty(words); !r)
                    return r;
            } else if (key == "comment") {
                readComment(words);
            }
            // "obj_info" and anything else: skipped, as assimp skips them (comments too; they
            // are kept only for what the file says about itself, such as a particle radius).
        }
        // Debian's assimp 5.2.5 reads header lines until it finds end_header, and loops for
        // ever at the end of a file without one (found by tests/fuzz: a file cut short inside
        // its header hung the importer).
        return problemNoLine(std::string("the PLY header has no end_header line") +
                             (m_fileBytes <= kMaxPlyHeaderBytes ? " (the file is cut short?)"
                                                                : " in its first 1 MiB"));
    }

    /// assimp allocates for the declared elements before reading them (found by tests/fuzz: a
    /// PLY declaring 8.9e24 vertices on its 276th header line made it read at the end of the
    /// file for ever). Refuses a header whose vertices and faces cannot fit in the file: each
    /// vertex needs at least 6 bytes as text ("0 0 0\n") or 3 binary, each face 8 as text
    /// ("3 0 1 2\n") or 4 binary. Then a count of 2^32 or more, kept from readElement so that
    /// this more telling answer comes first.
    Result<void> checkDeclaredCounts() const {
        double vertices = 0, faces = 0;
        for (const PlyElement& e : m_header.elements) {
            vertices += e.name == "vertex" ? e.declared : 0;
            faces += e.name == "face" ? e.declared : 0;
        }
        const bool binary = m_header.encoding != PlyEncoding::Ascii;
        const double needed = binary ? vertices * 3 + faces * 4 : vertices * 6 + faces * 8;
        if (needed > double(m_fileBytes) && m_content == PlyContent::Points) {
            // Points have no faces to speak of: most likely the file was cut short.
            char text[120];
            std::snprintf(text, sizeof text, "%.0f vertices, more than its %.0f bytes can hold",
                          vertices, double(m_fileBytes));
            return sluice::fail(ErrorCode::Truncated,
                                m_shown + " is truncated: its header declares " + text);
        }
        if (needed > double(m_fileBytes))
            return problemNoLine(declaresMoreThanTheFileHolds(vertices, faces, m_fileBytes));
        if (m_countTooLarge)
            return *m_countTooLarge;
        return {};
    }

    Result<void> readFormat(const std::vector<std::string_view>& words) {
        if (words.size() != 3)
            return problem("\"format\" needs an encoding and a version");
        const std::string encoding = lowered(words[1]);
        if (encoding == "ascii")
            m_header.encoding = PlyEncoding::Ascii;
        else if (encoding == "binary_little_endian")
            m_header.encoding = PlyEncoding::LittleEndian;
        else if (encoding == "binary_big_endian")
            m_header.encoding = PlyEncoding::BigEndian;
        else
            return problem("unknown encoding \"" + std::string(words[1]) + "\"");
        return {};
    }

    Result<void> readElement(const std::vector<std::string_view>& words) {
        if (words.size() != 3)
            return problem("\"element\" needs a name and a count");
        const std::string count(words[2]);
        const bool digits = count.find_first_not_of("0123456789") == std::string::npos;
        const std::uint64_t value =
            digits && count.size() <= 10 ? std::strtoull(count.c_str(), nullptr, 10) : ~0ull;
        const Error tooLarge = problem("the count of element \"" + std::string(words[1]) +
                                       "\" is not a whole number below 2^32");
        if (!digits || count.empty())
            return tooLarge;
        // A whole number too large: said after the header, by checkDeclaredCounts.
        if (value > 0xffffffffull && !m_countTooLarge)
            m_countTooLarge = tooLarge;
        for (const PlyElement& e : m_header.elements)
            if (e.name == words[1])
                return problem("element \"" + e.name + "\" is declared twice");
        PlyElement element;
        element.name = std::string(words[1]);
        element.count = std::min<std::uint64_t>(value, 0xffffffffull);
        element.declared = std::strtod(count.c_str(), nullptr);
        m_header.elements.push_back(std::move(element));
        return {};
    }

    void readComment(const std::vector<std::string_view>& words) {
        PlyComment comment;
        comment.line = m_line;
        for (std::size_t n = 1; n < words.size(); ++n)
            comment.text += (n > 1 ? " " : "") + std::string(words[n]);
        m_header.comments.push_back(std::move(comment));
    }

    Result<void> readProperty(const std::vector<std::string_view>& words) {
        if (m_header.elements.empty())
            return problem("a property before any element");
        PlyElement& element = m_header.elements.back();
        PlyProperty property;
        if (words.size() >= 2 && words[1] == "list") {
            if (words.size() != 5)
                return problem("\"property list\" needs a count type, a value type and a name");
            const std::optional<PlyScalar> count = scalarNamed(words[2]);
            const std::optional<PlyScalar> value = scalarNamed(words[3]);
            if (!count || !value)
                return problem("unknown type \"" + std::string(count ? words[3] : words[2]) + "\"");
            if (!isInteger(*count))
                return problem("a list count must have an integer type, not \"" +
                               std::string(words[2]) + "\"");
            property.list = true;
            property.count = *count;
            property.value = *value;
            property.name = std::string(words[4]);
        } else {
            if (words.size() != 3)
                return problem("\"property\" needs a type and a name");
            const std::optional<PlyScalar> value = scalarNamed(words[1]);
            if (!value)
                return problem("unknown type \"" + std::string(words[1]) + "\"");
            property.value = *value;
            property.name = std::string(words[2]);
        }
        for (const PlyProperty& p : element.properties)
            if (p.name == property.name)
                return problem("property \"" + p.name + "\" of element \"" + element.name +
                               "\" is declared twice");
        const bool indices = (element.name == "face" || element.strips()) && property.list &&
                             (property.name == "vertex_indices" || property.name == "vertex_index");
        if (indices) {
            if (!isInteger(property.value))
                return problem("vertex indices must have an integer type, not a float");
            if (element.indexList < 0)
                element.indexList = int(element.properties.size());
        }
        element.properties.push_back(std::move(property));
        return {};
    }

    /// A file without vertex positions or faces has nothing to bake: said here, so that
    /// assimp never reads a PLY file sluice-bake would refuse anyway (found by tests/fuzz: a
    /// binary file of no elements crashed assimp's reader). Points need no faces.
    Result<void> checkSomethingToBake() {
        const PlyElement* vertices = nullptr;
        bool faces = false;
        for (const PlyElement& e : m_header.elements) {
            if (e.name == "vertex") {
                vertices = &e;
                m_header.vertexCount = e.count;
            }
            if (e.indexList >= 0 && e.count > 0)
                faces = true;
        }
        if (!faces && m_content == PlyContent::Mesh)
            return sluice::fail(ErrorCode::EmptyMesh,
                                m_shown + ": no triangles (the PLY header declares no faces)");
        for (const char* axis : {"x", "y", "z"}) {
            const bool found =
                vertices &&
                std::any_of(vertices->properties.begin(), vertices->properties.end(),
                            [&](const PlyProperty& p) { return !p.list && p.name == axis; });
            if (!found)
                return problemNoLine(std::string("the PLY vertex element has no scalar \"") + axis +
                                     "\" property: no positions to read");
        }
        return {};
    }

    std::uint64_t m_fileBytes = 0;
    const std::string& m_shown;
    PlyContent m_content = PlyContent::Mesh;
    std::size_t m_line = 0;
    PlyHeader m_header;
    std::optional<Error> m_countTooLarge; ///< the first element count of 2^32 or more
};

} // namespace

std::size_t bytesOf(PlyScalar s) {
    switch (s) {
    case PlyScalar::Int8:
    case PlyScalar::UInt8:
        return 1;
    case PlyScalar::Int16:
    case PlyScalar::UInt16:
        return 2;
    case PlyScalar::Int32:
    case PlyScalar::UInt32:
    case PlyScalar::Float32:
        return 4;
    case PlyScalar::Float64:
        return 8;
    }
    return 0;
}

bool isInteger(PlyScalar s) {
    return s != PlyScalar::Float32 && s != PlyScalar::Float64;
}

/// The inclusive range an integer type holds.
std::pair<double, double> rangeOf(PlyScalar s) {
    switch (s) {
    case PlyScalar::Int8:
        return {-128.0, 127.0};
    case PlyScalar::UInt8:
        return {0.0, 255.0};
    case PlyScalar::Int16:
        return {-32768.0, 32767.0};
    case PlyScalar::UInt16:
        return {0.0, 65535.0};
    case PlyScalar::Int32:
        return {-2147483648.0, 2147483647.0};
    case PlyScalar::UInt32:
        return {0.0, 4294967295.0};
    default:
        return {-HUGE_VAL, HUGE_VAL};
    }
}

Result<PlyHeader> readPlyHeader(const std::string& head, std::uint64_t fileBytes,
                                const std::string& shown, PlyContent content) {
    return PlyHeaderReader(fileBytes, shown, content).read(head);
}

Error plyProblem(const std::string& shown, std::size_t line, const std::string& what) {
    return sluice::fail(ErrorCode::MeshImport,
                        shown + ": line " + std::to_string(line) + ": " + what);
}

Error plyProblem(const std::string& shown, const std::string& what) {
    return sluice::fail(ErrorCode::MeshImport, shown + ": " + what);
}

} // namespace sluice::bake::detail
