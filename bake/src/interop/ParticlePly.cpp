// Particle positions and radii out of a PLY point file: the hardened header, a checked body walk.
#include "interop/ParticlePly.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "import/PlyCheck.h"
#include "import/PlyHeader.h"
#include "sluice/format/support/AtomicFile.h"
#include "sluice/format/support/Hash.h"

namespace sluice::bake::detail {
namespace {

/// Reads the values of a PLY body one at a time, binary (either byte order) or ASCII words,
/// never past its end. After a false return, error() says what went wrong.
class PlyBodyReader {
public:
    PlyBodyReader(std::span<const std::byte> bytes, std::size_t at, PlyEncoding encoding)
        : m_bytes(bytes), m_at(at), m_encoding(encoding) {}

    /// The next value, of type `type`, as a double. False at the end of the data (Truncated)
    /// or, in ASCII, at a word that is not a number (MeshImport).
    bool next(PlyScalar type, double& value) {
        return m_encoding == PlyEncoding::Ascii ? nextWord(value) : nextBinary(type, value);
    }

    /// [bytes] what is left to read.
    std::uint64_t left() const { return m_bytes.size() - m_at; }

    /// Set when next() returned false: the code and what was found ("" for the end).
    ErrorCode errorCode() const { return m_errorCode; }
    const std::string& badWord() const { return m_badWord; }

private:
    bool nextBinary(PlyScalar type, double& value) {
        const std::size_t size = bytesOf(type);
        if (m_bytes.size() - m_at < size) {
            m_errorCode = ErrorCode::Truncated;
            return false;
        }
        unsigned char raw[8] = {};
        std::memcpy(raw, m_bytes.data() + m_at, size);
        m_at += size;
        // Both encodings read as little-endian below: a big-endian value is reversed first.
        static_assert(std::endian::native == std::endian::little, "PLY reader assumes a "
                                                                  "little-endian host");
        if (m_encoding == PlyEncoding::BigEndian)
            std::reverse(raw, raw + size);
        value = decode(type, raw);
        return true;
    }

    static double decode(PlyScalar type, const unsigned char* raw) {
        auto as = [raw]<class T>(T) {
            T v;
            std::memcpy(&v, raw, sizeof v);
            return double(v);
        };
        switch (type) {
        case PlyScalar::Int8:
            return as(std::int8_t{});
        case PlyScalar::UInt8:
            return as(std::uint8_t{});
        case PlyScalar::Int16:
            return as(std::int16_t{});
        case PlyScalar::UInt16:
            return as(std::uint16_t{});
        case PlyScalar::Int32:
            return as(std::int32_t{});
        case PlyScalar::UInt32:
            return as(std::uint32_t{});
        case PlyScalar::Float32:
            return as(float{});
        case PlyScalar::Float64:
            return as(double{});
        }
        return 0.0;
    }

    bool nextWord(double& value) {
        auto space = [this](std::size_t i) {
            return std::isspace(static_cast<unsigned char>(m_bytes[i])) != 0;
        };
        while (m_at < m_bytes.size() && space(m_at))
            ++m_at;
        std::size_t end = m_at;
        while (end < m_bytes.size() && !space(end) && end - m_at < 64)
            ++end;
        if (end == m_at) {
            m_errorCode = ErrorCode::Truncated;
            return false;
        }
        const std::string word(reinterpret_cast<const char*>(m_bytes.data()) + m_at, end - m_at);
        m_at = end;
        char* stop = nullptr;
        value = std::strtod(word.c_str(), &stop);
        if (stop != word.c_str() + word.size()) {
            m_errorCode = ErrorCode::MeshImport;
            m_badWord = word;
            return false;
        }
        return true;
    }

    std::span<const std::byte> m_bytes;
    std::size_t m_at = 0;
    PlyEncoding m_encoding = PlyEncoding::Ascii;
    ErrorCode m_errorCode = ErrorCode::Truncated;
    std::string m_badWord;
};

/// Where x, y, z and radius sit among the vertex element's properties.
struct VertexLayout {
    std::size_t axis[3] = {};
    std::optional<std::size_t> radius;
};

Result<VertexLayout> vertexLayout(const PlyElement& vertex, const std::string& shown) {
    VertexLayout layout;
    const char* names[4] = {"x", "y", "z", "radius"};
    for (int n = 0; n < 4; ++n) {
        const auto it = std::find_if(vertex.properties.begin(), vertex.properties.end(),
                                     [&](const PlyProperty& p) { return p.name == names[n]; });
        if (it == vertex.properties.end())
            continue; // x, y and z are there: readPlyHeader checked
        if (it->list)
            return plyProblem(shown, std::string("the vertex property \"") + names[n] +
                                         "\" is a list; a particle needs one number");
        const std::size_t index = std::size_t(it - vertex.properties.begin());
        if (n < 3)
            layout.axis[n] = index;
        else
            layout.radius = index;
    }
    return layout;
}

/// The error for a read that failed inside instance `i` of `element`.
Error bodyProblem(const PlyBodyReader& body, const std::string& shown, const PlyElement& element,
                  std::uint64_t i) {
    const std::string where = "element \"" + element.name + "\" " + std::to_string(i + 1) + " of " +
                              std::to_string(element.count);
    if (body.errorCode() == ErrorCode::Truncated)
        return fail(ErrorCode::Truncated,
                    shown + " is truncated: the data ends inside " + where + "; write it again");
    return plyProblem(shown, where + ": \"" + body.badWord() + "\" is not a number");
}

/// Reads (and forgets) the values of one property: one scalar, or a list's count and items.
bool skipProperty(PlyBodyReader& body, const PlyProperty& property) {
    double value = 0.0;
    if (!body.next(property.list ? property.count : property.value, value))
        return false;
    // An ASCII count may be any number: a list never holds more than its count type can say.
    const std::uint64_t items =
        property.list ? std::uint64_t(std::clamp(value, 0.0, 4294967295.0)) : 0;
    for (std::uint64_t k = 0; k < items; ++k)
        if (!body.next(property.value, value))
            return false;
    return true;
}

/// Reads (and forgets) one instance of an element.
bool skipInstance(PlyBodyReader& body, const PlyElement& element) {
    for (const PlyProperty& p : element.properties)
        if (!skipProperty(body, p))
            return false;
    return true;
}

/// [bytes] The least one instance of `element` takes: its scalars and list counts in binary,
/// a digit and a separator per value in ASCII.
std::uint64_t leastInstanceBytes(const PlyElement& element, PlyEncoding encoding) {
    std::uint64_t bytes = 0;
    for (const PlyProperty& p : element.properties)
        bytes += encoding == PlyEncoding::Ascii ? 2 : bytesOf(p.list ? p.count : p.value);
    return bytes;
}

/// Reads the vertex element's instances into `frame`, checking every value.
Result<void> readVertices(PlyBodyReader& body, const PlyElement& vertex, const VertexLayout& layout,
                          const std::string& shown, ParticleFrame& frame) {
    frame.positions.resize(vertex.count);
    if (layout.radius)
        frame.radii.resize(vertex.count);
    std::vector<double> values(vertex.properties.size());
    for (std::uint64_t i = 0; i < vertex.count; ++i) {
        for (std::size_t p = 0; p < vertex.properties.size(); ++p) {
            const PlyProperty& property = vertex.properties[p];
            if (property.list) {
                if (!skipProperty(body, property))
                    return bodyProblem(body, shown, vertex, i);
            } else if (!body.next(property.value, values[p])) {
                return bodyProblem(body, shown, vertex, i);
            }
        }
        const glm::dvec3 position(values[layout.axis[0]], values[layout.axis[1]],
                                  values[layout.axis[2]]);
        if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z))
            return fail(ErrorCode::NonFinite, shown + ": vertex " + std::to_string(i + 1) + " of " +
                                                  std::to_string(vertex.count) +
                                                  " has a non-finite coordinate");
        frame.positions[i] = position;
        if (!layout.radius)
            continue;
        const double radius = values[*layout.radius];
        if (!std::isfinite(radius))
            return fail(ErrorCode::NonFinite,
                        shown + ": vertex " + std::to_string(i + 1) + " has a non-finite radius");
        if (radius <= 0.0) {
            char text[80];
            std::snprintf(text, sizeof text, " has radius %g; a particle radius must be > 0",
                          radius);
            return fail(ErrorCode::InvalidArgument,
                        shown + ": vertex " + std::to_string(i + 1) + text);
        }
        frame.radii[i] = radius;
    }
    return {};
}

/// The radius a header records as "comment particle_radius R" (sluice-play's frames), if any.
Result<std::optional<double>> headerRadius(const PlyHeader& header, const std::string& shown) {
    constexpr std::string_view kKey = "particle_radius";
    std::optional<double> radius;
    for (const PlyComment& comment : header.comments) {
        const std::string_view text = comment.text;
        if (text.substr(0, kKey.size()) != kKey ||
            (text.size() > kKey.size() && text[kKey.size()] != ' '))
            continue; // another comment
        if (radius)
            return plyProblem(shown, comment.line, "a second \"comment particle_radius\"");
        const std::string value(text.substr(std::min(text.size(), kKey.size() + 1)));
        char* stop = nullptr;
        const double r = std::strtod(value.c_str(), &stop);
        if (value.empty() || stop != value.c_str() + value.size())
            return plyProblem(shown, comment.line,
                              "\"comment particle_radius\" needs one number, not \"" + value +
                                  "\"; write the file again or give --radius");
        if (!std::isfinite(r))
            return fail(ErrorCode::NonFinite,
                        shown + ": line " + std::to_string(comment.line) +
                            ": the header's particle radius \"" + value +
                            "\" is not finite; write the file again or give --radius");
        if (r <= 0.0)
            return fail(ErrorCode::InvalidArgument,
                        shown + ": line " + std::to_string(comment.line) +
                            ": the header's particle radius " + value +
                            " is not > 0; write the file again or give --radius");
        radius = r;
    }
    return radius;
}

} // namespace

Result<ParticleFrame> readParticlePly(const std::filesystem::path& path) {
    const std::string shown = "'" + path.string() + "'";
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
        return fail(ErrorCode::Io, "cannot open " + shown + ": no such file");
    Result<std::vector<std::byte>> bytes = format::readFileBytes(path, kMaxParticlePlyBytes);
    if (!bytes)
        return fail(bytes.error().code, shown + ": " + bytes.error().detail);
    const std::size_t headBytes = std::min<std::size_t>(bytes->size(), kMaxPlyHeaderBytes);
    const std::string head(reinterpret_cast<const char*>(bytes->data()), headBytes);
    if (!hasPlyMagic(head))
        return fail(ErrorCode::BadMagic, shown + " is not a PLY file (it does not start with "
                                                 "\"ply\")");
    Result<PlyHeader> header = readPlyHeader(head, bytes->size(), shown, PlyContent::Points);
    if (!header)
        return header.error();

    Result<std::optional<double>> radius = headerRadius(*header, shown);
    if (!radius)
        return radius.error();

    PlyBodyReader body(*bytes, std::size_t(header->bodyOffset), header->encoding);
    ParticleFrame frame;
    frame.headerRadius = *radius;
    frame.sourceHash = format::hex64(format::xxh3(*bytes));
    for (const PlyElement& element : header->elements) {
        if (element.name != "vertex") {
            for (std::uint64_t i = 0; i < element.count; ++i)
                if (!skipInstance(body, element))
                    return bodyProblem(body, shown, element, i);
            continue;
        }
        if (element.count == 0)
            return fail(ErrorCode::EmptyMesh, shown + " holds no particles (0 vertices)");
        Result<VertexLayout> layout = vertexLayout(element, shown);
        if (!layout)
            return layout.error();
        // Said before anything is allocated for them.
        if (element.count > body.left() / leastInstanceBytes(element, header->encoding))
            return fail(ErrorCode::Truncated,
                        shown + " is truncated: its " + std::to_string(body.left()) +
                            " bytes of data cannot hold the " + std::to_string(element.count) +
                            " vertices its header declares; write it again");
        if (Result<void> ok = readVertices(body, element, *layout, shown, frame); !ok)
            return ok.error();
        break; // what follows the vertices is not read
    }
    return frame;
}

} // namespace sluice::bake::detail
