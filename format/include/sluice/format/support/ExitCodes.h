// Process exit codes of sluice-bake and sluice-play, and the one mapping from an Error to them.
#pragma once

#include "sluice/format/support/Result.h"

namespace sluice {

// Scripts and CI tell "this machine cannot run it" (3) from bad input (2) and from a result
// that failed its check (1). The README's exit-code table lists the same.
inline constexpr int kExitOk = 0;          ///< success (validate: within the limits)
inline constexpr int kExitCheckFailed = 1; ///< validate over its limits; sluice-play --check failed
inline constexpr int kExitBadInput = 2;    ///< bad input: a file, mesh, asset, scene or argument
inline constexpr int kExitNoGlContext = 3; ///< no OpenGL 4.5 core context (or no display)
inline constexpr int kExitInternal = 4;    ///< an internal failure (our own shaders, a bug)

/// The exit code for an error: NoGlContext 3; our own shaders failing to compile or link 4 (the
/// input cannot cause that); everything else 2, GpuOutOfMemory included (the input is too large
/// for this GPU, as SizeOverflow says it is too large for its largest buffer).
constexpr int exitCodeFor(ErrorCode code) {
    switch (code) {
    case ErrorCode::NoGlContext:
        return kExitNoGlContext;
    case ErrorCode::ShaderCompile:
    case ErrorCode::ShaderLink:
        return kExitInternal;
    default:
        return kExitBadInput;
    }
}

/// exitCodeFor(error.code).
inline int exitCodeFor(const Error& error) {
    return exitCodeFor(error.code);
}

} // namespace sluice
