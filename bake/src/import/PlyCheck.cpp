// PLY pre-flight check: see PlyCheck.h.
#include "import/PlyCheck.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace sluice::bake::detail {

namespace {

/// The header is read up to its first 1 MiB (checkDeclaredCounts has already refused a header
/// without end_header in that much).
constexpr std::size_t kMaxHeaderBytes = std::size_t(1) << 20;

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::size_t bytesOf(Scalar s) {
    switch (s) {
    case Scalar::Int8:
    case Scalar::UInt8:
        return 1;
    case Scalar::Int16:
    case Scalar::UInt16:
        return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32:
        return 4;
    case Scalar::Float64:
        return 8;
    }
    return 0;
}

bool isInteger(Scalar s) {
    return s != Scalar::Float32 && s != Scalar::Float64;
}

/// The inclusive range an integer type holds.
std::pair<double, double> rangeOf(Scalar s) {
    switch (s) {
    case Scalar::Int8:
        return {-128.0, 127.0};
    case Scalar::UInt8:
        return {0.0, 255.0};
    case Scalar::Int16:
        return {-32768.0, 32767.0};
    case Scalar::UInt16:
        return {0.0, 65535.0};
    case Scalar::Int32:
        return {-2147483648.0, 2147483647.0};
    case Scalar::UInt32:
        return {0.0, 4294967295.0};
    default:
        return {-HUGE_VAL, HUGE_VAL};
    }
}

/// The type names of the format, old and new spellings.
std::optional<Scalar> scalarNamed(std::string_view word) {
    static constexpr std::pair<std::string_view, Scalar> kNames[] = {
        {"char", Scalar::Int8},      {"int8", Scalar::Int8},       {"uchar", Scalar::UInt8},
        {"uint8", Scalar::UInt8},    {"short", Scalar::Int16},     {"int16", Scalar::Int16},
        {"ushort", Scalar::UInt16},  {"uint16", Scalar::UInt16},   {"int", Scalar::Int32},
        {"int32", Scalar::Int32},    {"uint", Scalar::UInt32},     {"uint32", Scalar::UInt32},
        {"float", Scalar::Float32},  {"float32", Scalar::Float32}, {"double", Scalar::Float64},
        {"float64", Scalar::Float64}};
    const std::string name = lowered(word);
    for (const auto& [known, scalar] : kNames)
        if (name == known)
            return scalar;
    return std::nullopt;
}

struct Property {
    std::string name;
    bool list = false;
    Scalar count = Scalar::UInt8; // lists only
    Scalar value = Scalar::Float32;
};

struct Element {
    std::string name;
    std::uint64_t count = 0; ///< instances (below 2^32 once the header is accepted)
    double declared = 0.0;   ///< the count as the header writes it, however large
    std::vector<Property> properties;
    /// The list of vertex indices, for "face" and "tristrips"; -1 when there is none.
    int indexList = -1;
    /// Triangle strips, whose index lists may hold -1 (a strip break).
    bool strips() const { return name == "tristrips"; }
};

enum class Encoding { Ascii, LittleEndian, BigEndian };

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

/// Judges one file; every error goes through problem() (with the current line) or
/// problemNoLine(), which prefix the file.
class PlyChecker {
public:
    PlyChecker(const std::filesystem::path& path, const std::string& shown)
        : m_path(path), m_shown(shown) {}

    Result<void> run() {
        std::error_code ec;
        m_fileBytes = std::filesystem::file_size(m_path, ec);
        if (ec)
            return fail(ErrorCode::Io, m_shown + ": cannot read the file size");
        std::ifstream in(m_path, std::ios::binary);
        if (!in)
            return fail(ErrorCode::Io, m_shown + ": cannot open the file for reading");
        std::string head(std::size_t(std::min<std::uint64_t>(m_fileBytes, kMaxHeaderBytes)), '\0');
        in.read(head.data(), std::streamsize(head.size()));
        head.resize(std::size_t(in.gcount()));
        // assimp takes any file whose first three bytes are "ply" (found by tests/fuzz: "plyp"
        // on the first line got past a whole-line test into assimp's reader).
        if (!hasPlyMagic(head))
            return {}; // not PLY: assimp says what it is
        if (Result<void> r = readHeader(head); !r)
            return r;
        if (Result<void> r = checkSomethingToBake(); !r)
            return r;
        in.clear();
        in.seekg(std::streamoff(m_bodyOffset));
        return m_encoding == Encoding::Ascii ? readAsciiBody(in) : readBinaryBody(in);
    }

private:
    Error problem(const std::string& what) const {
        return sluice::fail(ErrorCode::MeshImport,
                            m_shown + ": line " + std::to_string(m_line) + ": " + what);
    }
    Error problemNoLine(const std::string& what) const {
        return sluice::fail(ErrorCode::MeshImport, m_shown + ": " + what);
    }

    // --- Header ---------------------------------------------------------------------------

    Result<void> readHeader(const std::string& head) {
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
                m_bodyOffset = at;
                m_bodyFirstLine = m_line + 1;
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
            }
            // "comment", "obj_info" and anything else: skipped, as assimp skips them.
        }
        // Debian's assimp 5.2.5 reads header lines until it finds end_header, and loops for
        // ever at the end of a file without one (found by tests/fuzz: a file cut short inside
        // its header hung the importer).
        return problemNoLine(
            std::string("the PLY header has no end_header line") +
            (m_fileBytes <= kMaxHeaderBytes ? " (the file is cut short?)" : " in its first 1 MiB"));
    }

    /// assimp allocates for the declared elements before reading them (found by tests/fuzz: a
    /// PLY declaring 8.9e24 vertices on its 276th header line made it read at the end of the
    /// file for ever). Refuses a header whose vertices and faces cannot fit in the file: each
    /// vertex needs at least 6 bytes as text ("0 0 0\n") or 3 binary, each face 8 as text
    /// ("3 0 1 2\n") or 4 binary. Then a count of 2^32 or more, kept from readElement so that
    /// this more telling answer comes first.
    Result<void> checkDeclaredCounts() const {
        double vertices = 0, faces = 0;
        for (const Element& e : m_elements) {
            vertices += e.name == "vertex" ? e.declared : 0;
            faces += e.name == "face" ? e.declared : 0;
        }
        const bool binary = m_encoding != Encoding::Ascii;
        const double needed = binary ? vertices * 3 + faces * 4 : vertices * 6 + faces * 8;
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
            m_encoding = Encoding::Ascii;
        else if (encoding == "binary_little_endian")
            m_encoding = Encoding::LittleEndian;
        else if (encoding == "binary_big_endian")
            m_encoding = Encoding::BigEndian;
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
        for (const Element& e : m_elements)
            if (e.name == words[1])
                return problem("element \"" + e.name + "\" is declared twice");
        Element element;
        element.name = std::string(words[1]);
        element.count = std::min<std::uint64_t>(value, 0xffffffffull);
        element.declared = std::strtod(count.c_str(), nullptr);
        m_elements.push_back(std::move(element));
        return {};
    }

    Result<void> readProperty(const std::vector<std::string_view>& words) {
        if (m_elements.empty())
            return problem("a property before any element");
        Element& element = m_elements.back();
        Property property;
        if (words.size() >= 2 && words[1] == "list") {
            if (words.size() != 5)
                return problem("\"property list\" needs a count type, a value type and a name");
            const std::optional<Scalar> count = scalarNamed(words[2]);
            const std::optional<Scalar> value = scalarNamed(words[3]);
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
            const std::optional<Scalar> value = scalarNamed(words[1]);
            if (!value)
                return problem("unknown type \"" + std::string(words[1]) + "\"");
            property.value = *value;
            property.name = std::string(words[2]);
        }
        for (const Property& p : element.properties)
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
    /// binary file of no elements crashed assimp's reader).
    Result<void> checkSomethingToBake() {
        const Element* vertices = nullptr;
        bool faces = false;
        for (const Element& e : m_elements) {
            if (e.name == "vertex") {
                vertices = &e;
                m_vertexCount = e.count;
            }
            if (e.indexList >= 0 && e.count > 0)
                faces = true;
        }
        if (!faces)
            return sluice::fail(ErrorCode::EmptyMesh,
                                m_shown + ": no triangles (the PLY header declares no faces)");
        for (const char* axis : {"x", "y", "z"}) {
            const bool found =
                vertices &&
                std::any_of(vertices->properties.begin(), vertices->properties.end(),
                            [&](const Property& p) { return !p.list && p.name == axis; });
            if (!found)
                return problemNoLine(std::string("the PLY vertex element has no scalar \"") + axis +
                                     "\" property: no positions to read");
        }
        return {};
    }

    // --- Body -----------------------------------------------------------------------------

    /// Whether `index` may stand in a vertex-index list of `element`.
    Result<void> checkIndex(const Element& element, double index, std::uint64_t instance) const {
        if (element.strips() && index == -1.0)
            return {};
        if (!(index >= 0.0 && index < double(m_vertexCount)))
            return problemAt(element, instance,
                             "vertex index " + numberText(index) +
                                 " is not below the vertex count " + std::to_string(m_vertexCount));
        return {};
    }

    /// An error about instance `instance` of `element`: its line for ASCII, its index for
    /// binary.
    Error problemAt(const Element& element, std::uint64_t instance, const std::string& what) const {
        if (m_encoding == Encoding::Ascii)
            return problem(what);
        return problemNoLine("\"" + element.name + "\" " + std::to_string(instance) + " of " +
                             std::to_string(element.count) + ": " + what);
    }

    static std::string numberText(double v) {
        char text[32];
        std::snprintf(text, sizeof text, "%.17g", v);
        return text;
    }

    Result<void> readAsciiBody(std::ifstream& in) {
        std::string text;
        m_line = m_bodyFirstLine - 1;
        for (const Element& element : m_elements) {
            for (std::uint64_t i = 0; i < element.count; ++i) {
                if (!std::getline(in, text))
                    return problemNoLine("the file ends after " + std::to_string(i) + " of its " +
                                         std::to_string(element.count) + " \"" + element.name +
                                         "\" elements");
                ++m_line;
                if (Result<void> r = readAsciiInstance(element, i, text); !r)
                    return r;
            }
        }
        return {};
    }

    Result<void> readAsciiInstance(const Element& element, std::uint64_t instance,
                                   const std::string& text) {
        const char* at = text.c_str();
        // The next number on the line into `value`; false at the end of the line or on a word
        // that is not a number.
        auto next = [&](double& value, bool& ended) {
            while (*at && std::isspace(static_cast<unsigned char>(*at)))
                ++at;
            ended = *at == '\0';
            if (ended)
                return false;
            char* end = nullptr;
            value = std::strtod(at, &end);
            if (end == at || (*end && !std::isspace(static_cast<unsigned char>(*end))))
                return false;
            at = end;
            return true;
        };
        const std::string what = "\"" + element.name + "\" " + std::to_string(instance);
        auto missing = [&](const Property& p, bool ended) {
            return problem(what + (ended ? ": the line ends before " : ": not a number for ") +
                           "property \"" + p.name + "\"");
        };
        for (std::size_t k = 0; k < element.properties.size(); ++k) {
            const Property& p = element.properties[k];
            double value = 0;
            bool ended = false;
            if (!next(value, ended))
                return missing(p, ended);
            if (!p.list)
                continue;
            const auto [lo, hi] = rangeOf(p.count);
            if (!(value == std::floor(value) && value >= std::max(lo, 0.0) && value <= hi))
                return problem(what + ": the count of list \"" + p.name + "\" is " +
                               numberText(value) + ", not a whole number its type holds");
            const auto items = std::uint64_t(value);
            const bool indices = int(k) == element.indexList;
            for (std::uint64_t j = 0; j < items; ++j) {
                if (!next(value, ended))
                    return problem(what + ": list \"" + p.name + "\" has " + std::to_string(j) +
                                   " of its " + std::to_string(items) + " values");
                if (indices) {
                    if (value != std::floor(value))
                        return problem(what + ": vertex index " + numberText(value) +
                                       " is not a whole number");
                    if (Result<void> r = checkIndex(element, value, instance); !r)
                        return r;
                }
            }
        }
        double extra = 0;
        bool ended = false;
        if (!next(extra, ended) && !ended)
            return problem(what + ": a word that is not a number after its properties");
        if (!ended)
            return problem(what + ": more values than element \"" + element.name +
                           "\" declares properties");
        return {};
    }

    /// Buffered reads and skips over the binary body; `remaining` bytes are left in the file.
    class Bytes {
    public:
        Bytes(std::ifstream& in, std::uint64_t remaining) : m_in(in), m_remaining(remaining) {}
        std::uint64_t remaining() const { return m_remaining + (m_end - m_at); }
        bool read(void* out, std::size_t n) {
            if (m_end - m_at < n && !fill(n))
                return false;
            std::memcpy(out, m_buffer.data() + m_at, n);
            m_at += n;
            return true;
        }
        bool skip(std::uint64_t n) {
            const std::uint64_t buffered = m_end - m_at;
            if (n <= buffered) {
                m_at += std::size_t(n);
                return true;
            }
            if (n > remaining())
                return false;
            const std::uint64_t beyond = n - buffered;
            m_at = m_end = 0;
            m_in.seekg(std::streamoff(beyond), std::ios::cur);
            m_remaining -= beyond;
            return bool(m_in);
        }

    private:
        bool fill(std::size_t n) {
            const std::size_t kept = m_end - m_at;
            std::memmove(m_buffer.data(), m_buffer.data() + m_at, kept);
            m_at = 0;
            m_end = kept;
            const std::size_t want =
                std::size_t(std::min<std::uint64_t>(m_buffer.size() - kept, m_remaining));
            m_in.read(m_buffer.data() + kept, std::streamsize(want));
            const auto got = std::size_t(m_in.gcount());
            m_end += got;
            m_remaining -= got;
            return m_end >= n;
        }
        std::ifstream& m_in;
        std::uint64_t m_remaining;
        std::array<char, 1 << 16> m_buffer{};
        std::size_t m_at = 0, m_end = 0;
    };

    /// One value of type `s` in the file's byte order.
    double decode(const unsigned char* raw, Scalar s) const {
        unsigned char b[8];
        const std::size_t n = bytesOf(s);
        std::memcpy(b, raw, n);
        const bool swap =
            (m_encoding == Encoding::BigEndian) != (std::endian::native == std::endian::big);
        if (swap)
            std::reverse(b, b + n);
        switch (s) {
        case Scalar::Int8:
            return double(std::int8_t(b[0]));
        case Scalar::UInt8:
            return double(b[0]);
        case Scalar::Int16: {
            std::int16_t v;
            std::memcpy(&v, b, 2);
            return v;
        }
        case Scalar::UInt16: {
            std::uint16_t v;
            std::memcpy(&v, b, 2);
            return v;
        }
        case Scalar::Int32: {
            std::int32_t v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Scalar::UInt32: {
            std::uint32_t v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Scalar::Float32: {
            float v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Scalar::Float64: {
            double v;
            std::memcpy(&v, b, 8);
            return v;
        }
        }
        return 0;
    }

    Result<void> readBinaryBody(std::ifstream& in) {
        Bytes bytes(in, m_fileBytes - std::min<std::uint64_t>(m_fileBytes, m_bodyOffset));
        for (const Element& element : m_elements) {
            const bool hasList = std::any_of(element.properties.begin(), element.properties.end(),
                                             [](const Property& p) { return p.list; });
            auto endsInside = [&](std::uint64_t i) {
                return problemNoLine("the file ends inside \"" + element.name + "\" " +
                                     std::to_string(i) + " of " + std::to_string(element.count));
            };
            if (!hasList) { // fixed size: one skip
                std::uint64_t stride = 0;
                for (const Property& p : element.properties)
                    stride += bytesOf(p.value);
                const std::uint64_t available = stride ? bytes.remaining() / stride : element.count;
                if (available < element.count)
                    return endsInside(available);
                if (!bytes.skip(stride * element.count))
                    return endsInside(available);
                continue;
            }
            for (std::uint64_t i = 0; i < element.count; ++i) {
                for (std::size_t k = 0; k < element.properties.size(); ++k) {
                    const Property& p = element.properties[k];
                    if (!p.list) {
                        if (!bytes.skip(bytesOf(p.value)))
                            return endsInside(i);
                        continue;
                    }
                    unsigned char raw[8];
                    if (!bytes.read(raw, bytesOf(p.count)))
                        return endsInside(i);
                    const double items = decode(raw, p.count);
                    if (items < 0)
                        return problemAt(element, i,
                                         "list \"" + p.name + "\" has a negative count " +
                                             numberText(items));
                    if (int(k) != element.indexList) {
                        if (!bytes.skip(std::uint64_t(items) * bytesOf(p.value)))
                            return endsInside(i);
                        continue;
                    }
                    for (std::uint64_t j = 0; j < std::uint64_t(items); ++j) {
                        if (!bytes.read(raw, bytesOf(p.value)))
                            return endsInside(i);
                        if (Result<void> r = checkIndex(element, decode(raw, p.value), i); !r)
                            return r;
                    }
                }
            }
        }
        return {};
    }

    const std::filesystem::path& m_path;
    const std::string& m_shown;
    std::uint64_t m_fileBytes = 0;
    std::uint64_t m_bodyOffset = 0;
    std::size_t m_line = 0, m_bodyFirstLine = 0;
    Encoding m_encoding = Encoding::Ascii;
    std::vector<Element> m_elements;
    std::uint64_t m_vertexCount = 0; ///< of the "vertex" element, once the header is read
    std::optional<Error> m_countTooLarge; ///< the first element count of 2^32 or more
};

} // namespace

Result<void> checkPlyFile(const std::filesystem::path& path, const std::string& shown) {
    return PlyChecker(path, shown).run();
}

std::string lowered(std::string_view text) {
    std::string out(text);
    for (char& c : out)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::string declaresMoreThanTheFileHolds(double vertices, double faces, std::uint64_t fileBytes) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "the header declares %.0f vertices and %.0f faces, more than its %.0f bytes can "
                  "hold",
                  vertices, faces, double(fileBytes));
    return text;
}

bool hasPlyMagic(std::string_view start) {
    return start.size() >= 3 && lowered(start.substr(0, 3)) == "ply";
}

} // namespace sluice::bake::detail
