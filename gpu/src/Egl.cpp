// Headless EGL: NVIDIA's device platform, then Mesa's surfaceless one, each verified with GL 4.5.
#include "Egl.h"

#include <cstdlib>
#include <optional>
#include <string_view>
#include <vector>

#include <sluice_glad/egl.h>

#include "DisplayRegistry.h"
#include "sluice/gpu/Context.h"
#include "sluice/gpu/Gl.h"
#include "sluice/gpu/Program.h"

namespace sluice::gpu {
namespace {

// Tokens of extensions that the glad2 EGL header does not carry.
constexpr EGLint kDrmDeviceFileExt = 0x3233;     // EGL_EXT_device_drm
constexpr EGLint kDrmRenderNodeFileExt = 0x3377; // EGL_EXT_device_drm_render_node
constexpr EGLint kDeviceRendererExt = 0x335F;    // EGL_EXT_device_query_name (EGL_RENDERER_EXT)
const EGLConfig kNoConfig = static_cast<EGLConfig>(nullptr); // EGL_NO_CONFIG_KHR

const char* eglErrorName(EGLint error) {
    switch (error) {
    case EGL_SUCCESS:
        return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
        return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
        return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
        return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
        return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
        return "EGL_CONTEXT_LOST";
    default:
        return "unknown EGL error";
    }
}

bool hasExtension(const char* list, std::string_view name) {
    if (list == nullptr)
        return false;
    std::string_view rest(list);
    while (!rest.empty()) {
        std::size_t end = rest.find(' ');
        if (rest.substr(0, end) == name)
            return true;
        if (end == std::string_view::npos)
            break;
        rest.remove_prefix(end + 1);
    }
    return false;
}

GLADapiproc loadGlFunction(const char* name) {
    return eglGetProcAddress(name);
}

/// Client extensions, read once per createEglContext: loading EGL for a display later
/// overwrites glad's flags with that display's extensions.
struct ClientExtensions {
    bool platformBase = false;
    bool platformDevice = false;
    bool deviceEnumeration = false;
    bool deviceQuery = false;
    bool platformSurfaceless = false;
};

struct Settings {
    std::string platform; // auto, device or surfaceless
    int deviceIndex = -1;
    bool debug = false;
};

Result<Settings> resolveSettings(const ContextOptions& options) {
    Settings settings;
    settings.debug = options.debug;
    settings.platform = options.platform;
    std::string source = "ContextOptions::platform";
    if (settings.platform.empty()) {
        const char* env = std::getenv("SLUICE_EGL_PLATFORM");
        settings.platform = env != nullptr && *env != '\0' ? env : "auto";
        source = "SLUICE_EGL_PLATFORM";
    }
    if (settings.platform != "auto" && settings.platform != "device" &&
        settings.platform != "surfaceless")
        return fail(ErrorCode::NoGlContext, "unknown EGL platform '" + settings.platform +
                                                "' (from " + source +
                                                "); use device, surfaceless or auto");
    settings.deviceIndex = options.deviceIndex;
    if (settings.deviceIndex < 0) {
        const char* env = std::getenv("SLUICE_EGL_DEVICE");
        if (env != nullptr && *env != '\0') {
            char* end = nullptr;
            long index = std::strtol(env, &end, 10);
            if (*end != '\0' || index < 0 || index > 1024)
                return fail(ErrorCode::NoGlContext, std::string("SLUICE_EGL_DEVICE='") + env +
                                                        "' is not an EGL device index (0, 1, ...)");
            settings.deviceIndex = static_cast<int>(index);
        }
    }
    return settings;
}

/// An EGL or GL setup failure: every one of them means "no usable context here".
Error noContext(std::string detail) {
    return fail(ErrorCode::NoGlContext, std::move(detail));
}

/// Checks the current context: GL 4.5 core, and a compute shader compiles.
Result<void> verifyGl() {
    GLint major = 0;
    GLint minor = 0;
    GLint profile = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    std::string what =
        std::string("'") + (version ? version : "?") + "' on '" + (renderer ? renderer : "?") + "'";
    if (major < 4 || (major == 4 && minor < 5))
        return noContext("GL " + what + " is older than 4.5");
    if ((profile & GL_CONTEXT_CORE_PROFILE_BIT) == 0)
        return noContext("GL " + what + " is not a core profile");
    auto program = Program::compute("context check", R"(
        layout(local_size_x = 32) in;
        layout(std430, binding = 0) buffer Data { float data[]; };
        void main() { data[gl_GlobalInvocationID.x] *= 2.0; }
    )");
    if (!program)
        return noContext("GL " + what +
                         " cannot compile a compute shader: " + program.error().detail);
    return {};
}

/// Creates and verifies a context on one display into `out`; on failure cleans up and says why.
Result<void> tryDisplay(EGLDisplay display, const Settings& settings, EglContext& out) {
    if (display == EGL_NO_DISPLAY)
        return noContext("eglGetPlatformDisplayEXT failed: " + lastEglError());
    if (auto acquired = acquireDisplay(display); !acquired)
        return acquired.error();
    out = EglContext{};
    out.display = display;
    auto failWith = [&](std::string reason) {
        destroyEglContext(out);
        return noContext(std::move(reason));
    };

    // Reload EGL for this display: its version decides which core functions exist, and its
    // extensions which context and surface features do.
    if (sluice_gladLoaderLoadEGL(display) == 0)
        return failWith("could not load the EGL functions for the display");
    const char* displayExtensions = eglQueryString(display, EGL_EXTENSIONS);
    const char* eglVersion = eglQueryString(display, EGL_VERSION);
    const char* eglVendor = eglQueryString(display, EGL_VENDOR);
    out.eglVersion =
        std::string(eglVersion ? eglVersion : "?") + " (" + (eglVendor ? eglVendor : "?") + ")";
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE)
        return failWith("eglBindAPI(EGL_OPENGL_API) failed (" + lastEglError() +
                        "): this EGL offers no desktop OpenGL");

    const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                    EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = kNoConfig;
    EGLint configCount = 0;
    if (eglChooseConfig(display, configAttribs, &config, 1, &configCount) != EGL_TRUE ||
        configCount < 1) {
        if (!hasExtension(displayExtensions, "EGL_KHR_no_config_context"))
            return failWith("no EGL config with EGL_OPENGL_BIT and pbuffers, and no "
                            "EGL_KHR_no_config_context");
        config = kNoConfig;
    }

    std::vector<EGLint> contextAttribs = {
        EGL_CONTEXT_MAJOR_VERSION,       4,
        EGL_CONTEXT_MINOR_VERSION,       5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
    if (settings.debug) {
        if (sluice_GLAD_EGL_VERSION_1_5) {
            contextAttribs.insert(contextAttribs.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
        } else {
            contextAttribs.insert(contextAttribs.end(),
                                  {EGL_CONTEXT_FLAGS_KHR, EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR});
        }
    }
    contextAttribs.push_back(EGL_NONE);
    if (!sluice_GLAD_EGL_VERSION_1_5 && !sluice_GLAD_EGL_KHR_create_context)
        return failWith("EGL " + out.eglVersion +
                        " has neither EGL 1.5 nor "
                        "EGL_KHR_create_context, so no 4.5 core context can be requested");
    out.context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs.data());
    if (out.context == EGL_NO_CONTEXT)
        return failWith("eglCreateContext(OpenGL 4.5 core) failed: " + lastEglError());

    if (!sluice_GLAD_EGL_KHR_surfaceless_context) {
        if (config == kNoConfig)
            return failWith("no EGL_KHR_surfaceless_context and no config for a pbuffer");
        const EGLint pbufferAttribs[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        out.surface = eglCreatePbufferSurface(display, config, pbufferAttribs);
        if (out.surface == EGL_NO_SURFACE)
            return failWith("no EGL_KHR_surfaceless_context and eglCreatePbufferSurface failed: " +
                            lastEglError());
    }
    if (auto current = makeEglContextCurrent(out); !current)
        return failWith(current.error().detail);
    if (sluice_gladLoadGL(&loadGlFunction) == 0)
        return failWith("could not load the OpenGL functions through eglGetProcAddress");
    if (auto verified = verifyGl(); !verified)
        return failWith(verified.error().detail);
    return {};
}

std::string deviceDescription(EGLDeviceEXT device, const ClientExtensions& client) {
    if (!client.deviceQuery || eglQueryDeviceStringEXT == nullptr)
        return {};
    const char* extensions = eglQueryDeviceStringEXT(device, EGL_EXTENSIONS);
    if (hasExtension(extensions, "EGL_MESA_device_software"))
        return "software";
    std::string name;
    if (hasExtension(extensions, "EGL_EXT_device_query_name")) {
        if (const char* renderer = eglQueryDeviceStringEXT(device, kDeviceRendererExt))
            name = renderer;
    }
    const char* node = nullptr;
    if (hasExtension(extensions, "EGL_EXT_device_drm"))
        node = eglQueryDeviceStringEXT(device, kDrmDeviceFileExt);
    if (node == nullptr && hasExtension(extensions, "EGL_EXT_device_drm_render_node"))
        node = eglQueryDeviceStringEXT(device, kDrmRenderNodeFileExt);
    if (node != nullptr)
        name += name.empty() ? std::string(node) : " (" + std::string(node) + ")";
    return name;
}

void tryDevicePlatform(const Settings& settings, const ClientExtensions& client,
                       std::vector<std::string>& tried, std::optional<EglContext>& found) {
    if (!client.platformBase || !client.platformDevice || !client.deviceEnumeration) {
        tried.push_back("device platform: EGL lacks EGL_EXT_platform_device or "
                        "EGL_EXT_device_enumeration");
        return;
    }
    EGLint count = 0;
    if (eglQueryDevicesEXT(0, nullptr, &count) != EGL_TRUE || count <= 0) {
        tried.push_back("device platform: no EGL devices (" + lastEglError() + ")");
        return;
    }
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
    eglQueryDevicesEXT(count, devices.data(), &count);
    devices.resize(static_cast<std::size_t>(count));

    std::vector<int> order;
    if (settings.deviceIndex >= 0) {
        if (settings.deviceIndex >= count) {
            tried.push_back("device platform: device index " +
                            std::to_string(settings.deviceIndex) + " out of range (" +
                            std::to_string(count) + " EGL devices)");
            return;
        }
        order.push_back(settings.deviceIndex);
    } else {
        // GPUs before software rasterizers: glvnd lists vendors in no particular order.
        for (int pass = 0; pass < 2; ++pass)
            for (int i = 0; i < count; ++i)
                if ((deviceDescription(devices[i], client) == "software") == (pass == 1))
                    order.push_back(i);
    }
    for (int index : order) {
        std::string name = deviceDescription(devices[static_cast<std::size_t>(index)], client);
        std::string label =
            "device " + std::to_string(index) + (name.empty() ? "" : " (" + name + ")");
        EGLDisplay display = eglGetPlatformDisplayEXT(
            EGL_PLATFORM_DEVICE_EXT, devices[static_cast<std::size_t>(index)], nullptr);
        EglContext egl;
        Result<void> made = tryDisplay(display, settings, egl);
        if (made) {
            egl.platform = "device";
            egl.deviceIndex = index;
            egl.deviceName = name;
            found = std::move(egl);
            return;
        }
        tried.push_back(label + ": " + made.error().detail);
    }
}

void trySurfacelessPlatform(const Settings& settings, const ClientExtensions& client,
                            std::vector<std::string>& tried, std::optional<EglContext>& found) {
    if (!client.platformBase || !client.platformSurfaceless) {
        tried.push_back("surfaceless platform: EGL lacks EGL_MESA_platform_surfaceless");
        return;
    }
    EGLDisplay display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EglContext egl;
    if (Result<void> made = tryDisplay(display, settings, egl); !made) {
        tried.push_back("surfaceless platform: " + made.error().detail);
        return;
    }
    egl.platform = "surfaceless";
    found = std::move(egl);
}

} // namespace

std::string lastEglError() {
    return eglErrorName(eglGetError());
}

Result<EglContext> createEglContext(const ContextOptions& options) {
    if (forkedFromGlProcess())
        return fail(ErrorCode::NoGlContext,
                    "this process was forked while its parent had an OpenGL context open; the GL "
                    "driver's threads do not survive fork(), so no context can open here. Start "
                    "worker processes with the spawn or forkserver method (Python: "
                    "multiprocessing.get_context(\"spawn\")) or open contexts only after the "
                    "fork");
    auto settings = resolveSettings(options);
    if (!settings)
        return settings.error();

    // First load without a display: only client extensions (platforms, device enumeration).
    if (sluice_gladLoaderLoadEGL(EGL_NO_DISPLAY) == 0)
        return fail(ErrorCode::NoGlContext,
                    "could not load libEGL.so.1; install an EGL implementation: the NVIDIA "
                    "driver's, or Mesa's (libegl1 and libegl-mesa0)");
    ClientExtensions client;
    client.platformBase = sluice_GLAD_EGL_EXT_platform_base != 0;
    client.platformDevice = sluice_GLAD_EGL_EXT_platform_device != 0;
    client.deviceEnumeration =
        sluice_GLAD_EGL_EXT_device_enumeration != 0 || sluice_GLAD_EGL_EXT_device_base != 0;
    client.deviceQuery =
        sluice_GLAD_EGL_EXT_device_query != 0 || sluice_GLAD_EGL_EXT_device_base != 0;
    client.platformSurfaceless = sluice_GLAD_EGL_MESA_platform_surfaceless != 0;

    std::vector<std::string> tried;
    std::optional<EglContext> found;
    if (settings->platform != "surfaceless")
        tryDevicePlatform(*settings, client, tried, found);
    // A chosen device index means that device or nothing.
    bool surfacelessAllowed = settings->platform == "surfaceless" ||
                              (settings->platform == "auto" && settings->deviceIndex < 0);
    if (!found && surfacelessAllowed)
        trySurfacelessPlatform(*settings, client, tried, found);
    if (found)
        return std::move(*found);

    std::string detail = "no OpenGL 4.5 core context with compute shaders (EGL platform '" +
                         settings->platform + "'). Tried:";
    for (const auto& attempt : tried)
        detail += "\n  - " + attempt;
    detail += "\nWith an NVIDIA GPU install its driver with EGL (libEGL_nvidia.so.0); without a "
              "GPU install Mesa (libegl-mesa0, libgl1-mesa-dri) for llvmpipe. "
              "SLUICE_EGL_PLATFORM=device|surfaceless|auto forces a platform.";
    return fail(ErrorCode::NoGlContext, std::move(detail));
}

Result<void> makeEglContextCurrent(const EglContext& egl) {
    if (eglMakeCurrent(egl.display, egl.surface, egl.surface, egl.context) == EGL_TRUE)
        return {};
    return noContext(std::string("eglMakeCurrent failed: ") + lastEglError() +
                     (egl.surface == EGL_NO_SURFACE ? " (without a surface)" : ""));
}

void destroyEglContext(EglContext& egl) {
    if (egl.display == EGL_NO_DISPLAY)
        return;
    if (egl.context != EGL_NO_CONTEXT) {
        if (eglGetCurrentContext != nullptr && eglGetCurrentContext() == egl.context)
            eglMakeCurrent(egl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(egl.display, egl.context);
    }
    if (egl.surface != EGL_NO_SURFACE)
        eglDestroySurface(egl.display, egl.surface);
    releaseDisplay(egl.display);
    // Both exist from EGL 1.4 on, which the first failure paths may not have loaded yet.
    if (eglGetCurrentContext != nullptr && eglReleaseThread != nullptr &&
        eglGetCurrentContext() == EGL_NO_CONTEXT)
        eglReleaseThread();
    egl = EglContext{};
}

} // namespace sluice::gpu
