// Private: EGL displays shared by Contexts, counted, and what a fork() child may do with them.
#pragma once

#include "sluice/format/support/Result.h"

namespace sluice::gpu {

/// Initializes `display` (an EGLDisplay) unless another Context already did, and counts one
/// more user; NoGlContext with the EGL error if eglInitialize fails.
Result<void> acquireDisplay(void* display);

/// Counts one user less and terminates `display` when it was the last (joining the driver's
/// worker threads). A display that was never acquired is left alone.
void releaseDisplay(void* display);

} // namespace sluice::gpu
