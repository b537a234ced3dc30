// GL debug output: what the glDebugMessageCallback of a debug context records, and the policy.
#pragma once

#include <string>

#include "sluice/gpu/Gl.h"

namespace sluice::gpu {

/// What a debug context does with GL errors (type GL_DEBUG_TYPE_ERROR or high severity).
///
/// Either way the callback records them (delivery is synchronous, so a message arrives during
/// the GL call that caused it) and Context::takeDebugMessages() returns them.
enum class DebugPolicy {
    /// Fail loudly: every gpu library call (compile, dispatch, upload, download, allocation) and
    /// Context::assertNoDebugErrors() end in a SLUICE_ASSERT failure if an error was recorded.
    /// Errors the library returns as values (ShaderCompile, GpuOutOfMemory) are not recorded.
    Assert,
    /// Only record; the caller inspects takeDebugMessages() (e.g. to print or return them).
    Collect,
};

/// One message from GL debug output.
struct DebugMessage {
    GLenum source = 0;   ///< GL_DEBUG_SOURCE_*
    GLenum type = 0;     ///< GL_DEBUG_TYPE_*
    GLuint id = 0;       ///< implementation-defined message id
    GLenum severity = 0; ///< GL_DEBUG_SEVERITY_*
    std::string text;

    /// True for errors and high-severity messages, the ones DebugPolicy::Assert fails on.
    bool isError() const;
    /// "GL error (high, api): <text>"
    std::string describe() const;
};

} // namespace sluice::gpu
