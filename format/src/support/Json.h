// Untrusted JSON text to a DOM, and typed reads that fail naming the JSON path (SceneIO's base).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

// cereal's JSON support: json.hpp brings in the rapidjson cereal ships (or the system one, on
// distributions that unbundle it) and makes rapidjson's internal asserts throw.
#include <cereal/archives/json.hpp>
#include <glm/vec3.hpp>

#include "sluice/format/support/Result.h"

namespace sluice::format::detail {

#if defined(CEREAL_RAPIDJSON_NAMESPACE)
namespace rj = CEREAL_RAPIDJSON_NAMESPACE;
#else
namespace rj = RAPIDJSON_NAMESPACE;
#endif

/// Deepest nesting of arrays and objects parseJson accepts; scene files need 5.
inline constexpr std::size_t kMaxJsonDepth = 32;

/// A problem at one place in a JSON document. Thrown by the typed reads below and caught by the
/// caller, which turns it into an Error naming the file.
struct JsonError : std::runtime_error {
    JsonError(ErrorCode code, std::string path, std::string problem);
    ErrorCode code;
    std::string path;    ///< JSON path, "" for the top level
    std::string problem; ///< what is wrong, for people
};

/// [[noreturn]] shorthand: throw JsonError(code, path, problem).
[[noreturn]] void throwAt(ErrorCode code, const std::string& path, std::string problem);

/// Where and why the text is not JSON (or is JSON nested too deeply).
struct JsonSyntaxError {
    ErrorCode code;     ///< BadMetadata, or NonFinite for a number beyond the double range
    std::size_t line;   ///< 1-based
    std::size_t column; ///< 1-based, in bytes
    std::string path;   ///< JSON path of the value being read when it failed, "" at the top
    std::string problem;
};

/// Parses `json` (UTF-8, an optional byte-order mark is skipped) into `doc`, strictly: no
/// comments, no trailing commas, valid UTF-8; NaN, Inf, Infinity (and negatives) are accepted as
/// numbers so that the reader can reject them naming their path. Never recurses, so hostile
/// nesting cannot overflow the stack; deeper than kMaxJsonDepth is an error.
std::optional<JsonSyntaxError> parseJson(std::string_view json, rj::Document& doc);

/// The whole text of `file`, refused unread when over `maxBytes`. Messages name the file, its
/// kind `what` ("the scene file", "the manifest") and the limit `limitName` ("scene-file
/// limit"): Io (missing, not a regular file, unreadable), SizeOverflow (over the limit).
Result<std::string> readTextFile(const std::filesystem::path& file, std::string_view what,
                                 std::string_view limitName, std::uintmax_t maxBytes);

/// "a" + "b" -> "a.b"; "" + "b" -> "b". Keys are shown as displayKey shows them.
std::string joinKey(const std::string& path, std::string_view key);
/// "a" + 2 -> "a[2]".
std::string joinIndex(const std::string& path, std::size_t index);
/// The path for messages: "(top level)" for "".
std::string displayPath(const std::string& path);
/// A key as messages show it: printable ASCII kept, other bytes as \xNN, cut after 64 bytes.
std::string displayKey(std::string_view key);
/// Shortest text that reads back as the same double ("1.5", "1e+300", "NaN", "-Infinity").
std::string formatNumber(double value);
/// Same for a float: 0.02f -> "0.02".
std::string formatFloat(float value);
/// "a number", "a string", "an array of 2 elements", "an object", "true", "null", ...
std::string describe(const rj::Value& value);

/// A JSON object whose keys were checked against the keys it may have. The constructor throws
/// BadMetadata if `value` is not an object, has a key twice, or has a key not in `keys` (the
/// message suggests the closest known key (closestMatch), or lists them all).
class JsonObject {
public:
    JsonObject(const rj::Value& value, std::string path,
               std::initializer_list<std::string_view> keys);

    /// The value of `key`, or nullptr when absent.
    const rj::Value* find(std::string_view key) const;
    /// The value of `key`; throws BadMetadata "missing required key" when absent.
    const rj::Value& require(std::string_view key) const;
    /// True when `key` is present.
    bool has(std::string_view key) const { return find(key) != nullptr; }
    /// Path of the object's member `key`.
    std::string pathOf(std::string_view key) const { return joinKey(m_path, key); }
    /// Path of the object itself.
    const std::string& path() const { return m_path; }

private:
    const rj::Value& m_value;
    std::string m_path;
};

/// A finite number (BadMetadata if not a number, NonFinite for NaN or infinity).
double readNumber(const rj::Value& value, const std::string& path);
/// readNumber, and within the float range (NonFinite beyond +-FLT_MAX).
float readFloat(const rj::Value& value, const std::string& path);
/// An integral number (4 and 4.0 are fine, 4.5 is BadMetadata) in [lo, hi] (InvalidArgument
/// "N is out of range [lo, hi]" otherwise).
std::int64_t readInteger(const rj::Value& value, const std::string& path, std::int64_t lo,
                         std::int64_t hi);
/// A string (BadMetadata otherwise).
std::string readString(const rj::Value& value, const std::string& path);
/// An array of 3 numbers, each readFloat.
glm::vec3 readVec3(const rj::Value& value, const std::string& path);
/// Checks that `value` is an array (BadMetadata otherwise) and returns it.
const rj::Value& requireArray(const rj::Value& value, const std::string& path);

/// What a kind of JSON file is called in messages, and its size limit.
struct JsonFileKind {
    std::string_view noun;      ///< "the scene", "the manifest": "cannot read the scene: ..."
    std::string_view fileNoun;  ///< "the scene file", "the manifest": readTextFile's `what`
    std::string_view limitName; ///< "scene-file limit"
    std::uintmax_t maxBytes;    ///< [bytes] larger text is refused unparsed (SizeOverflow)
};

/// Parses `json` (text of `file`, a `kind`) with parseJson and hands the document to `read`,
/// which returns a T or throws JsonError. Every failure comes back as an Error naming the file:
/// syntax errors with line, column and JSON path, JsonError with its path, out of memory as
/// SizeOverflow, any other exception (a rapidjson internal assert) as BadMetadata.
template <class T, class Read>
Result<T> parseJsonText(std::string_view json, const std::filesystem::path& file,
                        const JsonFileKind& kind, Read&& read) {
    const std::string name = file.string();
    if (json.size() > kind.maxBytes)
        return fail(ErrorCode::SizeOverflow, name + ": " + std::to_string(json.size()) +
                                                 " bytes, more than the " +
                                                 std::string(kind.limitName) + " of " +
                                                 std::to_string(kind.maxBytes));
    try {
        rj::Document doc;
        if (const auto e = parseJson(json, doc))
            return fail(e->code, name + ":" + std::to_string(e->line) + ":" +
                                     std::to_string(e->column) + ": " + displayPath(e->path) +
                                     ": " + e->problem);
        return read(static_cast<const rj::Document&>(doc));
    } catch (const JsonError& e) {
        return fail(e.code, name + ": " + displayPath(e.path) + ": " + e.problem);
    } catch (const std::bad_alloc&) {
        return fail(ErrorCode::SizeOverflow,
                    name + ": out of memory while reading " + std::string(kind.noun));
    } catch (const std::exception& e) {
        // cereal::RapidJSONException from a rapidjson internal assert, or anything else.
        return fail(ErrorCode::BadMetadata,
                    name + ": cannot read " + std::string(kind.noun) + ": " + e.what());
    }
}

/// The file's text through readTextFile, then parseJsonText.
template <class T, class Read>
Result<T> readJsonFile(const std::filesystem::path& file, const JsonFileKind& kind, Read&& read) {
    Result<std::string> text = readTextFile(file, kind.fileNoun, kind.limitName, kind.maxBytes);
    if (!text)
        return text.error();
    return parseJsonText<T>(*text, file, kind, std::forward<Read>(read));
}

} // namespace sluice::format::detail
