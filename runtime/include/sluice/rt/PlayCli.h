// The sluice-play command line: loads a scene and its colliders and plays it.
#pragma once

#include "sluice/format/Result.h"

namespace sluice::rt {

inline constexpr int kPlayExitOk = 0;          ///< success
inline constexpr int kPlayExitCheckFailed = 1; ///< --check: a non-finite particle or one inside a collider
inline constexpr int kPlayExitBadInput = 2;    ///< bad scene, collider asset or argument
inline constexpr int kPlayExitNoGlContext = 3; ///< no OpenGL 4.5 core context
inline constexpr int kPlayExitInternal = 4;    ///< an unexpected internal failure

/// The exit code for an error: NoGlContext 3, shader compile/link failures 4, anything else
/// (files, scenes, assets, arguments, a missing ffmpeg) 2.
int playExitCode(const Error& error);

/// Prints "sluice-play: MESSAGE" on stderr and returns playExitCode(error).
int reportFailure(const Error& error);

/// Runs sluice-play with the given arguments; returns the process exit code. Never throws.
int runPlay(int argc, char** argv);

} // namespace sluice::rt
