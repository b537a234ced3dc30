// PLY pre-flight check: the file's header (PlyHeader.cpp), then a walk over its body; see
// PlyCheck.h.
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
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "import/PlyHeader.h"

namespace sluice::bake::detail {

namespace {

/// A value of type T from its bytes, as a double.
template <class T> double as(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof value);
    return double(value);
}

/// Walks the body of one file against its header; every error goes through problem() (with
/// the current line) or problemNoLine(), which prefix the file.
class PlyBodyChecker {
public:
    PlyBodyChecker(const PlyHeader& header, std::uint64_t fileBytes, const std::string& shown)
        : m_header(header), m_fileBytes(fileBytes), m_shown(shown) {}

    /// Reads the body from `in`, which stands at its start.
    Result<void> run(std::ifstream& in) {
        return m_header.encoding == PlyEncoding::Ascii ? readAsciiBody(in) : readBinaryBody(in);
    }

private:
    Error problem(const std::string& what) const { return plyProblem(m_shown, m_line, what); }
    Error problemNoLine(const std::string& what) const { return plyProblem(m_shown, what); }

    /// Whether `index` may stand in a vertex-index list of `element`.
    Result<void> checkIndex(const PlyElement& element, double index, std::uint64_t instance) const {
        if (element.strips() && index == -1.0)
            return {};
        if (!(index >= 0.0 && index < double(m_header.vertexCount)))
            return problemAt(element, instance,
                             "vertex index " + numberText(index) +
                                 " is not below the vertex count " +
                                 std::to_string(m_header.vertexCount));
        return {};
    }

    /// An error about instance `instance` of `element`: its line for ASCII, its index for
    /// binary.
    Error problemAt(const PlyElement& element, std::uint64_t instance,
                    const std::string& what) const {
        if (m_header.encoding == PlyEncoding::Ascii)
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
        m_line = m_header.bodyFirstLine - 1;
        for (const PlyElement& element : m_header.elements) {
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

    Result<void> readAsciiInstance(const PlyElement& element, std::uint64_t instance,
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
        auto missing = [&](const PlyProperty& p, bool ended) {
            return problem(what + (ended ? ": the line ends before " : ": not a number for ") +
                           "property \"" + p.name + "\"");
        };
        for (std::size_t k = 0; k < element.properties.size(); ++k) {
            const PlyProperty& p = element.properties[k];
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
    double decode(const unsigned char* raw, PlyScalar s) const {
        unsigned char b[8];
        const std::size_t n = bytesOf(s);
        std::memcpy(b, raw, n);
        const bool swap = (m_header.encoding == PlyEncoding::BigEndian) !=
                          (std::endian::native == std::endian::big);
        if (swap)
            std::reverse(b, b + n);
        switch (s) {
        case PlyScalar::Int8:
            return as<std::int8_t>(b);
        case PlyScalar::UInt8:
            return as<std::uint8_t>(b);
        case PlyScalar::Int16:
            return as<std::int16_t>(b);
        case PlyScalar::UInt16:
            return as<std::uint16_t>(b);
        case PlyScalar::Int32:
            return as<std::int32_t>(b);
        case PlyScalar::UInt32:
            return as<std::uint32_t>(b);
        case PlyScalar::Float32:
            return as<float>(b);
        case PlyScalar::Float64:
            return as<double>(b);
        }
        return 0;
    }

    Result<void> readBinaryBody(std::ifstream& in) {
        Bytes bytes(in, m_fileBytes - std::min<std::uint64_t>(m_fileBytes, m_header.bodyOffset));
        for (const PlyElement& element : m_header.elements) {
            const bool hasList = std::any_of(element.properties.begin(), element.properties.end(),
                                             [](const PlyProperty& p) { return p.list; });
            auto endsInside = [&](std::uint64_t i) {
                return problemNoLine("the file ends inside \"" + element.name + "\" " +
                                     std::to_string(i) + " of " + std::to_string(element.count));
            };
            if (!hasList) { // fixed size: one skip
                std::uint64_t stride = 0;
                for (const PlyProperty& p : element.properties)
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
                    const PlyProperty& p = element.properties[k];
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

    const PlyHeader& m_header;
    std::uint64_t m_fileBytes = 0;
    const std::string& m_shown;
    std::size_t m_line = 0;
};

/// Reads the header and walks the body of a file whose first bytes hold the PLY magic.
Result<void> checkPly(const std::filesystem::path& path, const std::string& shown) {
    std::error_code ec;
    const std::uint64_t fileBytes = std::filesystem::file_size(path, ec);
    if (ec)
        return fail(ErrorCode::Io, shown + ": cannot read the file size");
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return fail(ErrorCode::Io, shown + ": cannot open the file for reading");
    std::string head(std::size_t(std::min<std::uint64_t>(fileBytes, kMaxPlyHeaderBytes)), '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(std::size_t(in.gcount()));
    // assimp takes any file whose first three bytes are "ply" (found by tests/fuzz: "plyp"
    // on the first line got past a whole-line test into assimp's reader).
    if (!hasPlyMagic(head))
        return {}; // not PLY: assimp says what it is
    Result<PlyHeader> header = readPlyHeader(head, fileBytes, shown);
    if (!header)
        return header.error();
    in.clear();
    in.seekg(std::streamoff(header->bodyOffset));
    return PlyBodyChecker(*header, fileBytes, shown).run(in);
}

} // namespace

Result<void> checkPlyFile(const std::filesystem::path& path, const std::string& shown) {
    return checkPly(path, shown);
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
