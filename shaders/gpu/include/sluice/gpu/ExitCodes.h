// Process exit codes that programs using the gpu library share (sluice-bake, sluice-play).
#pragma once

namespace sluice::gpu {

/// Exit code of a program that needs the GPU but got no OpenGL 4.5 core context with compute
/// shaders (Error code NoGlContext). Scripts and CI tell "this machine cannot run it" from a real
/// failure with it: 0 is success, 1 a failure, 2 a usage error, 3 no GL context.
inline constexpr int kExitNoGlContext = 3;

} // namespace sluice::gpu
