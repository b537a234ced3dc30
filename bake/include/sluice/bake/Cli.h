// The sluice-bake command line (CLI11): bake, validate, info, export, gl-info.
#pragma once

namespace sluice::bake {

/// Process exit codes of sluice-bake (also documented in the README).
inline constexpr int kExitOk = 0;           ///< success; validate: within the limits
inline constexpr int kExitOverLimits = 1;   ///< validate: over --max-error / --max-sign-errors
inline constexpr int kExitBadInput = 2;     ///< bad input: file, mesh, asset or argument
inline constexpr int kExitNoGlContext = 3;  ///< no OpenGL 4.5 core context with compute shaders
inline constexpr int kExitInternal = 4;     ///< an unexpected internal failure

/// Runs sluice-bake with the given arguments and returns the process exit code. Never throws.
int runCli(int argc, char** argv);

} // namespace sluice::bake
