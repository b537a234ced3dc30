// Private: finds an EGL display and creates a verified GL 4.5 core context on it.
#pragma once

#include <string>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Context.h"

namespace sluice::gpu {

/// A current EGL context with GL loaded and verified (4.5 core, compute shaders compile).
struct EglContext {
    void* display = nullptr; // EGLDisplay
    void* context = nullptr; // EGLContext
    void* surface = nullptr; // EGLSurface or EGL_NO_SURFACE
    std::string platform;    // "device" or "surfaceless"
    int deviceIndex = -1;
    std::string deviceName;
    std::string eglVersion;
};

/// Tries the platforms and devices `options` allows, in order, until one gives a verified
/// context; NoGlContext lists every attempt and its failure otherwise.
Result<EglContext> createEglContext(const ContextOptions& options);

/// Releases the context if current on this thread, destroys it and its surface, and terminates
/// the display when no other EglContext uses it. Leaves `egl` empty.
void destroyEglContext(EglContext& egl);

/// The name of eglGetError()'s code ("EGL_BAD_DISPLAY"), for messages.
std::string lastEglError();

/// Makes `egl` current on this thread; NoGlContext with the EGL error if that fails.
Result<void> makeEglContextCurrent(const EglContext& egl);

} // namespace sluice::gpu
