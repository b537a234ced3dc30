// Headless OpenGL 4.5 core context through EGL: NVIDIA's device platform, then Mesa's surfaceless.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Debug.h"

namespace sluice::gpu {

/// How createHeadless() looks for a context.
struct ContextOptions {
    /// "device" (EGL_EXT_platform_device: NVIDIA drivers, Mesa's software device),
    /// "surfaceless" (EGL_MESA_platform_surfaceless: Mesa, llvmpipe without a GPU) or "auto"
    /// (device, then surfaceless). Empty: the environment variable SLUICE_EGL_PLATFORM if set,
    /// else "auto". Any other name fails with NoGlContext.
    std::string platform;
    /// EGL device index for the device platform (order of eglQueryDevicesEXT). -1: the
    /// environment variable SLUICE_EGL_DEVICE if set, else every device, GPUs before software
    /// devices. An index >= 0 tries only that device (no surfaceless fallback in "auto").
    int deviceIndex = -1;
    /// Create a debug context and install a glDebugMessageCallback (see DebugPolicy).
    bool debug = false;
    /// What the debug callback does with errors; ignored unless debug is set.
    DebugPolicy debugPolicy = DebugPolicy::Assert;
};

/// What the context runs on and its compute limits.
struct ContextInfo {
    std::string vendor;      ///< GL_VENDOR
    std::string renderer;    ///< GL_RENDERER, e.g. "NVIDIA H100/PCIe/SSE2" or "llvmpipe (...)"
    std::string glVersion;   ///< GL_VERSION
    std::string glslVersion; ///< GL_SHADING_LANGUAGE_VERSION
    int glMajor = 0;         ///< GL_MAJOR_VERSION (>= 4)
    int glMinor = 0;         ///< GL_MINOR_VERSION (>= 5 when glMajor is 4)
    std::string platform;    ///< EGL platform used: "device" or "surfaceless"
    int deviceIndex = -1;    ///< EGL device index on the device platform, -1 otherwise
    std::string deviceName;  ///< device name or DRM node, "software", or empty if unknown
    std::string eglVersion;  ///< "1.5" and the EGL vendor string
    bool debug = false;      ///< a debug context with the debug callback installed

    glm::uvec3 maxWorkGroupCount{0};           ///< GL_MAX_COMPUTE_WORK_GROUP_COUNT [groups]
    glm::uvec3 maxWorkGroupSize{0};            ///< GL_MAX_COMPUTE_WORK_GROUP_SIZE [invocations]
    std::uint32_t maxWorkGroupInvocations = 0; ///< per work group
    std::uint32_t maxSharedMemoryBytes = 0;    ///< GL_MAX_COMPUTE_SHARED_MEMORY_SIZE [bytes]
    std::uint64_t maxSsboBytes = 0;            ///< GL_MAX_SHADER_STORAGE_BLOCK_SIZE [bytes]
    std::uint32_t maxSsboBindings = 0;         ///< GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS
    std::uint32_t maxComputeSsboBlocks = 0;    ///< GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS
    std::uint32_t max3DTextureSize = 0;        ///< GL_MAX_3D_TEXTURE_SIZE [texels per side]
    /// Dedicated GPU memory and what is free at creation [bytes], where the driver says
    /// (GL_NVX_gpu_memory_info); empty otherwise (llvmpipe).
    std::optional<std::uint64_t> gpuMemoryTotalBytes;
    std::optional<std::uint64_t> gpuMemoryAvailableBytes;

    /// Multi-line human-readable summary, for logs and `sluice-bake gl-info`.
    std::string describe() const;
};

struct DebugState;

/// An OpenGL 4.5 core context with compute shaders, without a window (RAII, move-only).
///
/// Creation makes it current on the calling thread. GL objects (Program, Buffer, ...) must be
/// destroyed before their context. Contexts may be created again after one is destroyed, and
/// several may live at once (each makeCurrent() before use).
class Context {
public:
    /// Tries the EGL platforms that `options` allows; for each: eglInitialize, bind the OpenGL
    /// API, create a 4.5 core context, make it current without a surface, load GL, check the
    /// version and compile a compute shader. NoGlContext lists every attempt and why it failed.
    /// The GL/EGL function pointers are process-wide: create contexts from one thread at a time.
    static Result<Context> createHeadless(const ContextOptions& options = {});

    Context(Context&& other) noexcept;
    Context& operator=(Context&& other) noexcept;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    /// Releases the context (eglMakeCurrent none, eglDestroyContext) and terminates its display
    /// once no other Context uses it.
    ~Context();

    const ContextInfo& info() const { return m_info; }

    /// Makes this context current on the calling thread (asserts on failure, and in a process
    /// that inherited the context across fork(): see forkedFromGlProcess).
    void makeCurrent() const;

    /// The same without asserting, for destructors: false where the context cannot be made
    /// current here (current on another thread, inherited across fork(), moved from), and then
    /// the caller must not touch its objects.
    bool tryMakeCurrent() const noexcept;

    /// Runs the embedded gpu_selftest.comp over `count` values and compares with the CPU
    /// (shared/GpuSelfTest.h); `maxGroupsPerDispatch` > 0 splits it with dispatchChunked.
    /// NoGlContext if the values differ, ShaderCompile/ShaderLink if it does not build.
    Result<void> selfTest(std::uint32_t count = 4096, std::uint32_t maxGroupsPerDispatch = 0) const;

    /// Messages recorded by the debug callback since the last call (empty without debug).
    std::vector<DebugMessage> takeDebugMessages();
    /// SLUICE_ASSERT failure listing the recorded errors, if any (drains them).
    void assertNoDebugErrors();

private:
    Context() = default;
    void release();

    void* m_display = nullptr; // EGLDisplay
    void* m_context = nullptr; // EGLContext
    void* m_surface = nullptr; // EGLSurface: a 1x1 pbuffer where surfaceless is unsupported
    ContextInfo m_info;
    std::unique_ptr<DebugState> m_debug; // heap, so the callback's pointer survives moves
};

/// True in a process made by fork() while its parent (or an ancestor) had a Context open. The
/// driver keeps worker threads per EGL display (llvmpipe's compute pool) and fork() copies none of
/// them, yet EGL would hand this process the same display again: its first dispatch would wait
/// forever. So such a process never calls into EGL: createHeadless fails at once with
/// NoGlContext saying why, and Contexts it inherited are dropped without a call. A process
/// started fresh (spawn, forkserver, exec) opens contexts as usual.
bool forkedFromGlProcess();

/// AddressSanitizer builds only (a no-op otherwise): keeps the GL driver libraries loaded in
/// the process (Mesa's *_dri.so) mapped until it exits. Mesa unloads its driver with its
/// display (eglTerminate, glfwTerminate); LeakSanitizer then no longer sees the driver's static
/// references to the caches it filled and reports them as leaks at exit. Context calls it
/// before every eglTerminate, whether or not a context was made; a program that makes its own
/// context (the GLFW viewer) calls it before glfwTerminate. Every other allocation is still
/// leak-checked.
void keepDriverLoadedForLeakChecks();

} // namespace sluice::gpu
