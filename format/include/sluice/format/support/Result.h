// Error values for untrusted input: Result<T> holds either a T or an Error naming what failed.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <variant>

#include "sluice/format/support/Assert.h"

namespace sluice {

/// One entry per way things fail. Shared by every module so errors cross module boundaries.
enum class ErrorCode {
    Io,                 ///< file cannot be opened, read, written or renamed
    Truncated,          ///< shorter than its header or its declared sizes say
    BadMagic,           ///< not a Sluice file of this kind
    UnsupportedVersion, ///< another major version
    BadHeader,          ///< header size or reserved fields wrong
    SizeMismatch,       ///< declared file size differs from the real one (e.g. trailing bytes)
    SizeOverflow,       ///< a size product overflows or exceeds a documented limit
    OffsetOutOfRange,   ///< a section lies outside the file or overlaps another
    ChecksumMismatch,   ///< payload or metadata bytes changed after writing
    BadMetadata,        ///< metadata block cannot be decoded or is inconsistent
    NonFinite,          ///< NaN or infinity where a finite number is required
    InvalidArgument,    ///< a command-line or API value out of range
    MeshImport,         ///< assimp could not read the mesh
    EmptyMesh,          ///< no triangles (empty file, point cloud, only lines)
    NoGlContext,        ///< no OpenGL 4.5 core context with compute shaders
    ShaderCompile,      ///< GLSL compile error (detail carries the info log)
    ShaderLink,         ///< GLSL link error (detail carries the info log)
    GpuOutOfMemory,     ///< allocation on the GPU failed or would exceed its memory
    Unsupported,        ///< valid input that this build cannot handle (e.g. a VDB grid type)
};

/// Short stable name of an error code, for messages and JSON ("Truncated").
std::string_view errorCodeName(ErrorCode code);

/// What went wrong: a code for programs, a detail for people. The detail names the file and,
/// where there is one, what to do about it ("re-bake with sluice-bake").
struct Error {
    ErrorCode code;
    std::string detail;

    /// "<detail> [<CodeName>]"
    std::string message() const { return detail + " [" + std::string(errorCodeName(code)) + "]"; }
};

/// Either a value or an Error. Accessing the wrong alternative is a broken contract (asserts).
template <class T> class [[nodiscard]] Result {
public:
    Result(T value) : m_v(std::move(value)) {}
    Result(Error error) : m_v(std::move(error)) {}

    bool ok() const { return m_v.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & {
        SLUICE_ASSERT(ok(), "Result::value() on an error");
        return std::get<0>(m_v);
    }
    const T& value() const& {
        SLUICE_ASSERT(ok(), "Result::value() on an error");
        return std::get<0>(m_v);
    }
    T&& value() && {
        SLUICE_ASSERT(ok(), "Result::value() on an error");
        return std::get<0>(std::move(m_v));
    }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

    const Error& error() const {
        SLUICE_ASSERT(!ok(), "Result::error() on a value");
        return std::get<1>(m_v);
    }

private:
    std::variant<T, Error> m_v;
};

/// Result of an operation with no value.
template <> class [[nodiscard]] Result<void> {
public:
    Result() = default;
    Result(Error error) : m_error(std::move(error)), m_ok(false) {}

    bool ok() const { return m_ok; }
    explicit operator bool() const { return ok(); }
    const Error& error() const {
        SLUICE_ASSERT(!ok(), "Result::error() on success");
        return m_error;
    }

private:
    Error m_error{ErrorCode::Io, {}};
    bool m_ok = true;
};

/// Builds an Error; reads well at return sites: `return fail(ErrorCode::Truncated, "...")`.
inline Error fail(ErrorCode code, std::string detail) { return Error{code, std::move(detail)}; }

} // namespace sluice
