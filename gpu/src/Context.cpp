// Headless context lifetime, its info and limits, and the debug-output policy.
#include "sluice/gpu/Context.h"

#include <string_view>
#include <utility>

#include "DebugState.h"
#include "Egl.h"
#include "sluice/format/support/Assert.h"
#include "sluice/gpu/Gl.h"

namespace sluice::gpu {
namespace {

// GL_NVX_gpu_memory_info and GL_ATI_meminfo tokens (not in the glad2 core 4.5 header) [KiB].
constexpr GLenum kNvxDedicatedVidmem = 0x9047;
constexpr GLenum kNvxCurrentAvailableVidmem = 0x9049;
constexpr GLenum kAtiTextureFreeMemory = 0x87FC;

std::string glString(GLenum name) {
    const auto* text = reinterpret_cast<const char*>(glGetString(name));
    return text != nullptr ? text : "";
}

bool hasGlExtension(std::string_view name) {
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    for (GLint i = 0; i < count; ++i) {
        const auto* ext =
            reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
        if (ext != nullptr && name == ext)
            return true;
    }
    return false;
}

std::uint32_t getUint(GLenum name) {
    GLint value = 0;
    glGetIntegerv(name, &value);
    return static_cast<std::uint32_t>(value);
}

void queryInfo(ContextInfo& info) {
    info.vendor = glString(GL_VENDOR);
    info.renderer = glString(GL_RENDERER);
    info.glVersion = glString(GL_VERSION);
    info.glslVersion = glString(GL_SHADING_LANGUAGE_VERSION);
    glGetIntegerv(GL_MAJOR_VERSION, &info.glMajor);
    glGetIntegerv(GL_MINOR_VERSION, &info.glMinor);
    for (GLuint axis = 0; axis < 3; ++axis) {
        GLint count = 0;
        GLint size = 0;
        glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, axis, &count);
        glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, axis, &size);
        info.maxWorkGroupCount[static_cast<int>(axis)] = static_cast<std::uint32_t>(count);
        info.maxWorkGroupSize[static_cast<int>(axis)] = static_cast<std::uint32_t>(size);
    }
    info.maxWorkGroupInvocations = getUint(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS);
    info.maxSharedMemoryBytes = getUint(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE);
    GLint64 ssbo = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &ssbo);
    info.maxSsboBytes = static_cast<std::uint64_t>(ssbo);
    info.maxSsboBindings = getUint(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS);
    info.maxComputeSsboBlocks = getUint(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS);
    info.max3DTextureSize = getUint(GL_MAX_3D_TEXTURE_SIZE);

    if (hasGlExtension("GL_NVX_gpu_memory_info")) {
        info.gpuMemoryTotalBytes = std::uint64_t{getUint(kNvxDedicatedVidmem)} * 1024;
        info.gpuMemoryAvailableBytes = std::uint64_t{getUint(kNvxCurrentAvailableVidmem)} * 1024;
    } else if (hasGlExtension("GL_ATI_meminfo")) {
        GLint free[4] = {0, 0, 0, 0};
        glGetIntegerv(kAtiTextureFreeMemory, free);
        info.gpuMemoryAvailableBytes = static_cast<std::uint64_t>(free[0]) * 1024;
    }
}

std::string mib(std::uint64_t bytes) {
    return std::to_string(bytes / (1024 * 1024)) + " MiB";
}

std::string triple(glm::uvec3 v) {
    return std::to_string(v.x) + " x " + std::to_string(v.y) + " x " + std::to_string(v.z);
}

} // namespace

std::string ContextInfo::describe() const {
    std::string text;
    text += "renderer:      " + renderer + " (" + vendor + ")\n";
    text +=
        "OpenGL:        " + glVersion + ", GLSL " + glslVersion + (debug ? ", debug" : "") + "\n";
    text += "EGL:           " + platform + " platform";
    if (deviceIndex >= 0)
        text += ", device " + std::to_string(deviceIndex);
    if (!deviceName.empty())
        text += " (" + deviceName + ")";
    text += ", EGL " + eglVersion + "\n";
    text += "compute:       groups " + triple(maxWorkGroupCount) + ", local size " +
            triple(maxWorkGroupSize) + ", " + std::to_string(maxWorkGroupInvocations) +
            " invocations, " + std::to_string(maxSharedMemoryBytes / 1024) + " KiB shared\n";
    text += "storage:       SSBO " + mib(maxSsboBytes) + " x " + std::to_string(maxSsboBindings) +
            " bindings (" + std::to_string(maxComputeSsboBlocks) +
            " blocks a compute shader), 3D texture " + std::to_string(max3DTextureSize) + "^3\n";
    text += "GPU memory:    ";
    text +=
        gpuMemoryTotalBytes ? mib(*gpuMemoryTotalBytes) + " total" : std::string("unknown total");
    if (gpuMemoryAvailableBytes)
        text += ", " + mib(*gpuMemoryAvailableBytes) + " available";
    text += "\n";
    return text;
}

Result<Context> Context::createHeadless(const ContextOptions& options) {
    auto egl = createEglContext(options);
    if (!egl)
        return egl.error();

    Context context;
    context.m_display = egl->display;
    context.m_context = egl->context;
    context.m_surface = egl->surface;
    ContextInfo& info = context.m_info;
    info.platform = egl->platform;
    info.deviceIndex = egl->deviceIndex;
    info.deviceName = egl->deviceName;
    info.eglVersion = egl->eglVersion;
    queryInfo(info);

    if (options.debug) {
        context.m_debug = std::make_unique<DebugState>();
        context.m_debug->policy = options.debugPolicy;
        installDebugCallback(*context.m_debug);
        info.debug = true;
    }
    setCurrentDebugState(context.m_debug.get());
    return context;
}

Context::Context(Context&& other) noexcept
    : m_display(std::exchange(other.m_display, nullptr)),
      m_context(std::exchange(other.m_context, nullptr)),
      m_surface(std::exchange(other.m_surface, nullptr)), m_info(std::move(other.m_info)),
      m_debug(std::move(other.m_debug)) {}

Context& Context::operator=(Context&& other) noexcept {
    if (this != &other) {
        release();
        m_display = std::exchange(other.m_display, nullptr);
        m_context = std::exchange(other.m_context, nullptr);
        m_surface = std::exchange(other.m_surface, nullptr);
        m_info = std::move(other.m_info);
        m_debug = std::move(other.m_debug);
    }
    return *this;
}

Context::~Context() {
    release();
}

void Context::release() {
    if (m_display == nullptr)
        return;
    if (m_debug != nullptr && currentDebugState() == m_debug.get())
        setCurrentDebugState(nullptr);
    if (forkedFromGlProcess()) {
        // The parent's context: any EGL call here could wait on the parent's driver threads.
        m_display = m_context = m_surface = nullptr;
        m_debug.reset();
        return;
    }
    EglContext egl;
    egl.display = m_display;
    egl.context = m_context;
    egl.surface = m_surface;
    destroyEglContext(egl);
    m_display = m_context = m_surface = nullptr;
    m_debug.reset();
}

void Context::makeCurrent() const {
    SLUICE_ASSERT(m_display != nullptr, "Context::makeCurrent on a moved-from context");
    SLUICE_ASSERT(
        !forkedFromGlProcess(),
        "Context::makeCurrent on a context inherited across fork() (forkedFromGlProcess)");
    EglContext egl;
    egl.display = m_display;
    egl.context = m_context;
    egl.surface = m_surface;
    const Result<void> current = makeEglContextCurrent(egl);
    SLUICE_ASSERT(current, current ? "" : current.error().detail.c_str());
    setCurrentDebugState(m_debug.get());
}

bool Context::tryMakeCurrent() const noexcept {
    if (m_display == nullptr || forkedFromGlProcess())
        return false;
    EglContext egl;
    egl.display = m_display;
    egl.context = m_context;
    egl.surface = m_surface;
    if (!makeEglContextCurrent(egl))
        return false;
    setCurrentDebugState(m_debug.get());
    return true;
}

std::vector<DebugMessage> Context::takeDebugMessages() {
    if (m_debug == nullptr)
        return {};
    std::lock_guard lock(m_debug->mutex);
    std::vector<DebugMessage> messages = std::move(m_debug->messages);
    m_debug->messages.clear();
    if (m_debug->dropped > 0) {
        messages.push_back(DebugMessage{
            GL_DEBUG_SOURCE_THIRD_PARTY, GL_DEBUG_TYPE_OTHER, 0, GL_DEBUG_SEVERITY_MEDIUM,
            std::to_string(m_debug->dropped) + " further messages were dropped"});
        m_debug->dropped = 0;
    }
    return messages;
}

void Context::assertNoDebugErrors() {
    if (m_debug == nullptr)
        return;
    std::vector<DebugMessage> errors = takeDebugErrors(*m_debug);
    std::string text = "GL debug output reported errors:";
    for (const auto& error : errors)
        text += "\n  " + error.describe();
    SLUICE_ASSERT(errors.empty(), text.c_str());
}

} // namespace sluice::gpu
