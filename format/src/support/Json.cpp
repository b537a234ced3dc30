// Strict, non-recursive JSON parsing that remembers where it was, and typed reads with paths.
#include "support/Json.h"

#include "sluice/format/support/Suggest.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>

namespace sluice::format::detail {

namespace {

// Iterative: no recursion however deep the text nests. NaN/Inf accepted so the reader can name
// the path of the non-finite value instead of reporting a bare syntax error at an offset.
// Not kParseFullPrecisionFlag (which cereal's own archive sets): rapidjson 1.1's full-precision
// path misreads hostile numbers (123456789012345678901234567890e300 came back as -3.8e-288;
// Tencent/rapidjson#1253, #1259, #2326), while the normal path is within 3 ulp of a double,
// far below the float every scene value ends up in, and overflows to infinity honestly.
constexpr unsigned kParseFlags =
    rj::kParseIterativeFlag | rj::kParseValidateEncodingFlag | rj::kParseNanAndInfFlag;

constexpr std::size_t kMaxKeyShown = 64; // [bytes]

// Forwards SAX events to a Document while tracking the JSON path of the value being read, so a
// syntax error can say where in the tree it happened, and refuses nesting past kMaxJsonDepth.
class TrackingHandler {
public:
    explicit TrackingHandler(rj::Document& doc) : m_doc(doc) {}

    bool Null() { return scalar(m_doc.Null()); }
    bool Bool(bool b) { return scalar(m_doc.Bool(b)); }
    bool Int(int i) { return scalar(m_doc.Int(i)); }
    bool Uint(unsigned u) { return scalar(m_doc.Uint(u)); }
    bool Int64(std::int64_t i) { return scalar(m_doc.Int64(i)); }
    bool Uint64(std::uint64_t u) { return scalar(m_doc.Uint64(u)); }
    bool Double(double d) { return scalar(m_doc.Double(d)); }
    bool RawNumber(const char* s, rj::SizeType n, bool copy) {
        return scalar(m_doc.RawNumber(s, n, copy));
    }
    bool String(const char* s, rj::SizeType n, bool copy) {
        return scalar(m_doc.String(s, n, copy));
    }
    bool StartObject() { return enter(false) && m_doc.StartObject(); }
    bool Key(const char* s, rj::SizeType n, bool copy) {
        m_frames.back().key.assign(s, n);
        m_frames.back().haveKey = true;
        return m_doc.Key(s, n, copy);
    }
    bool EndObject(rj::SizeType n) { return leave() && m_doc.EndObject(n); }
    bool StartArray() { return enter(true) && m_doc.StartArray(); }
    bool EndArray(rj::SizeType n) { return leave() && m_doc.EndArray(n); }

    bool tooDeep() const { return m_tooDeep; }

    // Path of the value being read: each open container, then the key or index in progress.
    std::string path() const {
        std::string p;
        for (const Frame& f : m_frames) {
            if (f.array)
                p = joinIndex(p, f.count);
            else if (f.haveKey)
                p = joinKey(p, f.key);
        }
        return p;
    }

private:
    struct Frame {
        bool array = false;
        std::size_t count = 0; // elements finished, for arrays
        std::string key;       // last key seen, for objects
        bool haveKey = false;
    };

    bool scalar(bool ok) {
        if (!m_frames.empty() && m_frames.back().array)
            ++m_frames.back().count;
        return ok;
    }
    bool enter(bool array) {
        if (m_frames.size() >= kMaxJsonDepth) {
            m_tooDeep = true;
            return false;
        }
        m_frames.push_back(Frame{array, 0, {}, false});
        return true;
    }
    bool leave() {
        if (!m_frames.empty())
            m_frames.pop_back();
        return scalar(true);
    }

    rj::Document& m_doc;
    std::vector<Frame> m_frames;
    bool m_tooDeep = false;
};

const char* parseErrorText(rj::ParseErrorCode code) {
    switch (code) {
    case rj::kParseErrorNone:
        return "no error";
    case rj::kParseErrorDocumentEmpty:
        return "the document is empty";
    case rj::kParseErrorDocumentRootNotSingular:
        return "text after the end of the top-level value";
    case rj::kParseErrorValueInvalid:
        return "invalid value";
    case rj::kParseErrorObjectMissName:
        return "missing a key (a quoted string) in an object";
    case rj::kParseErrorObjectMissColon:
        return "missing ':' after a key";
    case rj::kParseErrorObjectMissCommaOrCurlyBracket:
        return "missing ',' or '}' after an object member";
    case rj::kParseErrorArrayMissCommaOrSquareBracket:
        return "missing ',' or ']' after an array element";
    case rj::kParseErrorStringUnicodeEscapeInvalidHex:
        return "invalid \\u escape in a string";
    case rj::kParseErrorStringUnicodeSurrogateInvalid:
        return "invalid UTF-16 surrogate pair";
    case rj::kParseErrorStringEscapeInvalid:
        return "invalid escape in a string";
    case rj::kParseErrorStringMissQuotationMark:
        return "missing the closing '\"' of a string";
    case rj::kParseErrorStringInvalidEncoding:
        return "invalid UTF-8 in a string";
    case rj::kParseErrorNumberTooBig:
        return "number too big for a double";
    case rj::kParseErrorNumberMissFraction:
        return "missing digits after the decimal point";
    case rj::kParseErrorNumberMissExponent:
        return "missing digits in the exponent";
    case rj::kParseErrorTermination:
        return "parsing stopped";
    case rj::kParseErrorUnspecificSyntaxError:
        return "syntax error";
    }
    return "syntax error";
}

} // namespace

JsonError::JsonError(ErrorCode code_, std::string path_, std::string problem_)
    : std::runtime_error(problem_), code(code_), path(std::move(path_)),
      problem(std::move(problem_)) {}

void throwAt(ErrorCode code, const std::string& path, std::string problem) {
    throw JsonError(code, path, std::move(problem));
}

std::optional<JsonSyntaxError> parseJson(std::string_view json, rj::Document& doc) {
    const std::string_view bom = "\xEF\xBB\xBF";
    const std::size_t skipped = json.substr(0, 3) == bom ? 3 : 0;
    const std::string_view text = json.substr(skipped);

    TrackingHandler handler(doc);
    rj::ParseResult result;
    auto generate = [&](rj::Document&) {
        rj::MemoryStream stream(text.data(), text.size());
        rj::Reader reader;
        result = reader.Parse<kParseFlags>(stream, handler);
        return !result.IsError();
    };
    doc.Populate(generate);
    if (!result.IsError())
        return std::nullopt;

    JsonSyntaxError e;
    const std::size_t offset = skipped + std::min<std::size_t>(result.Offset(), text.size());
    const std::string_view before = json.substr(0, offset);
    const std::size_t lastNewline = before.rfind('\n');
    e.line = 1 + std::size_t(std::count(before.begin(), before.end(), '\n'));
    e.column = lastNewline == std::string_view::npos ? offset + 1 : offset - lastNewline;
    e.path = handler.path();
    if (handler.tooDeep()) {
        e.code = ErrorCode::BadMetadata;
        e.problem = "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels";
    } else {
        e.code = result.Code() == rj::kParseErrorNumberTooBig ? ErrorCode::NonFinite
                                                              : ErrorCode::BadMetadata;
        e.problem = std::string("JSON syntax error: ") + parseErrorText(result.Code());
    }
    return e;
}

Result<std::string> readTextFile(const std::filesystem::path& file, std::string_view what,
                                 std::string_view limitName, std::uintmax_t maxBytes) {
    namespace fs = std::filesystem;
    const std::string name = file.string();
    const std::string cannot = name + ": cannot read " + std::string(what) + ": ";
    std::error_code ec;
    const fs::file_status st = fs::status(file, ec);
    if (!fs::exists(st))
        return fail(ErrorCode::Io, cannot + (ec ? ec.message() : std::string("no such file")));
    if (!fs::is_regular_file(st))
        return fail(ErrorCode::Io, cannot + "not a regular file");
    const std::uintmax_t size = fs::file_size(file, ec);
    if (ec)
        return fail(ErrorCode::Io, cannot + ec.message());
    if (size > maxBytes)
        return fail(ErrorCode::SizeOverflow, name + ": " + std::to_string(size) +
                                                 " bytes, more than the " +
                                                 std::string(limitName) + " of " +
                                                 std::to_string(maxBytes));
    std::ifstream in(file, std::ios::binary);
    if (!in)
        return fail(ErrorCode::Io, cannot + "cannot open it");
    std::string text(std::size_t(size), '\0');
    in.read(text.data(), std::streamsize(size));
    if (std::uintmax_t(in.gcount()) != size)
        return fail(ErrorCode::Io, cannot + "read " + std::to_string(in.gcount()) + " of " +
                                       std::to_string(size) + " bytes");
    return text;
}

std::string joinKey(const std::string& path, std::string_view key) {
    return path.empty() ? displayKey(key) : path + "." + displayKey(key);
}

std::string joinIndex(const std::string& path, std::size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

std::string displayPath(const std::string& path) {
    return path.empty() ? "(top level)" : path;
}

std::string displayKey(std::string_view key) {
    std::string out;
    for (std::size_t i = 0; i < key.size() && i < kMaxKeyShown; ++i) {
        const auto c = static_cast<unsigned char>(key[i]);
        if (c >= 0x20 && c < 0x7F && c != '\\') {
            out += char(c);
        } else {
            static constexpr char kHex[] = "0123456789abcdef";
            out += "\\x";
            out += kHex[c >> 4];
            out += kHex[c & 15];
        }
    }
    if (key.size() > kMaxKeyShown)
        out += "...";
    return out;
}

// Plain digits for everyday magnitudes (0.0001, 16777217), exponents outside them (1e+30);
// either way the shortest text that reads back as the same value.
template <class T> std::string formatShortest(T value) {
    if (std::isnan(value))
        return "NaN";
    if (std::isinf(value))
        return value < 0 ? "-Infinity" : "Infinity";
    const T magnitude = std::fabs(value);
    const bool plain = magnitude == T(0) || (magnitude >= T(1e-5) && magnitude < T(1e16));
    char buf[400];
    const auto r = std::to_chars(buf, buf + sizeof buf, value,
                                 plain ? std::chars_format::fixed : std::chars_format::scientific);
    return std::string(buf, r.ptr);
}

std::string formatNumber(double value) {
    return formatShortest(value);
}

std::string formatFloat(float value) {
    return formatShortest(value);
}

std::string describe(const rj::Value& value) {
    switch (value.GetType()) {
    case rj::kNullType:
        return "null";
    case rj::kFalseType:
        return "false";
    case rj::kTrueType:
        return "true";
    case rj::kObjectType:
        return "an object";
    case rj::kArrayType:
        return "an array of " + std::to_string(value.Size()) +
               (value.Size() == 1 ? " element" : " elements");
    case rj::kStringType:
        return "a string";
    case rj::kNumberType:
        return "the number " + formatNumber(value.GetDouble());
    }
    return "an unknown value";
}

JsonObject::JsonObject(const rj::Value& value, std::string path,
                       std::initializer_list<std::string_view> keys)
    : m_value(value), m_path(std::move(path)) {
    if (!value.IsObject())
        throwAt(ErrorCode::BadMetadata, m_path, "expected an object, got " + describe(value));
    std::vector<std::string_view> seen;
    for (auto it = value.MemberBegin(); it != value.MemberEnd(); ++it) {
        const std::string_view key(it->name.GetString(), it->name.GetStringLength());
        if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
            std::string problem = "unknown key \"" + displayKey(key) + "\"";
            std::vector<std::string> known(keys.begin(), keys.end());
            const auto best = closestMatch(key, known);
            if (best) {
                problem += " (did you mean \"" + *best + "\"?)";
            } else {
                problem += " (known keys:";
                for (const std::string_view k : keys)
                    problem += " " + std::string(k);
                problem += ")";
            }
            throwAt(ErrorCode::BadMetadata, joinKey(m_path, key), std::move(problem));
        }
        if (std::find(seen.begin(), seen.end(), key) != seen.end())
            throwAt(ErrorCode::BadMetadata, joinKey(m_path, key),
                    "duplicate key \"" + displayKey(key) + "\"");
        seen.push_back(key);
    }
}

const rj::Value* JsonObject::find(std::string_view key) const {
    for (auto it = m_value.MemberBegin(); it != m_value.MemberEnd(); ++it)
        if (std::string_view(it->name.GetString(), it->name.GetStringLength()) == key)
            return &it->value;
    return nullptr;
}

const rj::Value& JsonObject::require(std::string_view key) const {
    const rj::Value* v = find(key);
    if (v == nullptr)
        throwAt(ErrorCode::BadMetadata, m_path,
                "missing required key \"" + std::string(key) + "\"");
    return *v;
}

double readNumber(const rj::Value& value, const std::string& path) {
    if (!value.IsNumber())
        throwAt(ErrorCode::BadMetadata, path, "expected a number, got " + describe(value));
    const double d = value.GetDouble();
    if (!std::isfinite(d))
        throwAt(ErrorCode::NonFinite, path, formatNumber(d) + " is not a finite number");
    return d;
}

float readFloat(const rj::Value& value, const std::string& path) {
    const double d = readNumber(value, path);
    if (std::fabs(d) > double(std::numeric_limits<float>::max()))
        throwAt(ErrorCode::NonFinite, path,
                formatNumber(d) + " is not finite as a 32-bit float (largest " +
                    formatFloat(std::numeric_limits<float>::max()) + ")");
    return static_cast<float>(d);
}

std::int64_t readInteger(const rj::Value& value, const std::string& path, std::int64_t lo,
                         std::int64_t hi) {
    if (!value.IsNumber())
        throwAt(ErrorCode::BadMetadata, path, "expected an integer, got " + describe(value));
    const double d = readNumber(value, path);
    if (!value.IsInt64() && d != std::floor(d))
        throwAt(ErrorCode::BadMetadata, path, "expected an integer, got " + formatNumber(d));
    // Compared as double first so a huge uint64 or 1e30 is reported as written.
    if (value.IsInt64() ? (value.GetInt64() < lo || value.GetInt64() > hi)
                        : (d < double(lo) || d > double(hi)))
        throwAt(ErrorCode::InvalidArgument, path,
                (value.IsInt64() ? std::to_string(value.GetInt64()) : formatNumber(d)) +
                    " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return value.IsInt64() ? value.GetInt64() : static_cast<std::int64_t>(d);
}

std::string readString(const rj::Value& value, const std::string& path) {
    if (!value.IsString())
        throwAt(ErrorCode::BadMetadata, path, "expected a string, got " + describe(value));
    return std::string(value.GetString(), value.GetStringLength());
}

glm::vec3 readVec3(const rj::Value& value, const std::string& path) {
    if (!value.IsArray() || value.Size() != 3)
        throwAt(ErrorCode::BadMetadata, path,
                "expected an array of 3 numbers [x, y, z], got " + describe(value));
    glm::vec3 v;
    for (rj::SizeType i = 0; i < 3; ++i)
        v[int(i)] = readFloat(value[i], joinIndex(path, i));
    return v;
}

const rj::Value& requireArray(const rj::Value& value, const std::string& path) {
    if (!value.IsArray())
        throwAt(ErrorCode::BadMetadata, path, "expected an array, got " + describe(value));
    return value;
}

} // namespace sluice::format::detail
