// EGL displays shared by Contexts: counted, terminated by the last user, and left alone by a
// process forked while one was open.
#include "DisplayRegistry.h"

#include <map>
#include <mutex>

#include <pthread.h>
#include <sluice_glad/egl.h>

#include "Egl.h"
#include "sluice/gpu/Context.h"

namespace sluice::gpu {
namespace {

// eglTerminate ends every context of a display, and Mesa hands out one display per platform and
// device, so two Contexts on the same display share it: the last one terminates it.
std::mutex g_displayMutex;
std::map<EGLDisplay, int> g_displayUsers;

// Set in a child of fork() whose parent had a display open, and kept in its own children. The
// driver's state for that display (llvmpipe's compute thread pool, its condition variables) came
// across, its threads did not: the first dispatch would wait for them forever. EGL hands the
// child that same display again (one per platform and device), so the child cannot use EGL.
bool g_forkedWithDisplay = false;

// pthread_atfork handlers: the registry is locked across fork(), so the child sees it whole.
void lockBeforeFork() {
    g_displayMutex.lock();
}
void unlockInParent() {
    g_displayMutex.unlock();
}
void forgetInChild() {
    g_forkedWithDisplay = g_forkedWithDisplay || !g_displayUsers.empty();
    g_displayUsers.clear(); // the parent's to terminate, not ours
    g_displayMutex.unlock();
}

} // namespace

bool forkedFromGlProcess() {
    return g_forkedWithDisplay;
}

Result<void> acquireDisplay(void* display) {
    // Registered before the first display opens: a fork before that has nothing to forget.
    static const int registered = pthread_atfork(lockBeforeFork, unlockInParent, forgetInChild);
    (void)registered;
    std::lock_guard lock(g_displayMutex);
    int& users = g_displayUsers[display];
    if (users == 0) {
        EGLint major = 0;
        EGLint minor = 0;
        if (eglInitialize(display, &major, &minor) != EGL_TRUE) {
            Error error = fail(ErrorCode::NoGlContext, "eglInitialize failed: " + lastEglError());
            g_displayUsers.erase(display);
            return error;
        }
    }
    ++users;
    return {};
}

void releaseDisplay(void* display) {
    std::lock_guard lock(g_displayMutex);
    auto it = g_displayUsers.find(display);
    if (it == g_displayUsers.end())
        return;
    if (--it->second == 0) {
        // Joins llvmpipe's worker threads; without it they can still run during exit.
        keepDriverLoadedForLeakChecks(); // ASan builds: eglTerminate would unload it
        eglTerminate(display);
        g_displayUsers.erase(it);
    }
}

} // namespace sluice::gpu
