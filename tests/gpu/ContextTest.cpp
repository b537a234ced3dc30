// Headless context creation, platform selection, lifetime, self-test and debug output.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Context.h"
#include "sluice/gpu/Gl.h"
#include "sluice/gpu/GpuShaders.h"

namespace sluice::gpu {
namespace {

/// Sets an environment variable for one scope (tests may run in one process).
class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : m_name(name) {
        if (const char* old = std::getenv(name))
            m_old = old;
        setenv(name, value, 1);
    }
    ~ScopedEnv() {
        if (m_old)
            setenv(m_name, m_old->c_str(), 1);
        else
            unsetenv(m_name);
    }

private:
    const char* m_name;
    std::optional<std::string> m_old;
};

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(HeadlessContext, CreatesAGl45CoreContextWithARendererName) {
    auto context = Context::createHeadless();
    ASSERT_TRUE(context) << context.error().message();
    const ContextInfo& info = context->info();
    std::printf("%s", info.describe().c_str());
    EXPECT_GE(info.glMajor * 10 + info.glMinor, 45);
    EXPECT_FALSE(info.renderer.empty());
    EXPECT_FALSE(info.glslVersion.empty());
    EXPECT_TRUE(info.platform == "device" || info.platform == "surfaceless") << info.platform;
    GLint profile = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    EXPECT_NE(profile & GL_CONTEXT_CORE_PROFILE_BIT, 0);
    EXPECT_FALSE(info.debug);
}

TEST(HeadlessContext, ReportsComputeLimitsAtLeastTheGl45Minimums) {
    auto context = Context::createHeadless();
    ASSERT_TRUE(context) << context.error().message();
    const ContextInfo& info = context->info();
    // OpenGL 4.5 core, table 23.67 (implementation-dependent compute shader limits).
    EXPECT_GE(info.maxWorkGroupCount.x, 65535u);
    EXPECT_GE(info.maxWorkGroupCount.y, 65535u);
    EXPECT_GE(info.maxWorkGroupCount.z, 65535u);
    EXPECT_GE(info.maxWorkGroupSize.x, 1024u);
    EXPECT_GE(info.maxWorkGroupSize.y, 1024u);
    EXPECT_GE(info.maxWorkGroupSize.z, 64u);
    EXPECT_GE(info.maxWorkGroupInvocations, 1024u);
    EXPECT_GE(info.maxSharedMemoryBytes, 32768u);
    EXPECT_GE(info.maxSsboBytes, std::uint64_t{1} << 27);
    EXPECT_GE(info.maxSsboBindings, 8u);
    EXPECT_GE(info.maxComputeSsboBlocks, 8u); // GL 4.5's minimum
    EXPECT_GE(info.max3DTextureSize, 2048u);
    if (info.gpuMemoryTotalBytes && info.gpuMemoryAvailableBytes) {
        EXPECT_LE(*info.gpuMemoryAvailableBytes, *info.gpuMemoryTotalBytes);
    }
}

TEST(HeadlessContext, RejectsAnUnknownPlatformNameWithNoGlContext) {
    ContextOptions options;
    options.platform = "vulkan";
    auto context = Context::createHeadless(options);
    ASSERT_FALSE(context);
    EXPECT_EQ(context.error().code, ErrorCode::NoGlContext);
    EXPECT_TRUE(contains(context.error().detail, "'vulkan'")) << context.error().detail;
    EXPECT_TRUE(contains(context.error().detail, "device, surfaceless or auto"));
}

TEST(HeadlessContext, TakesThePlatformFromSluiceEglPlatform) {
    ScopedEnv env("SLUICE_EGL_PLATFORM", "no-such-platform");
    auto context = Context::createHeadless();
    ASSERT_FALSE(context);
    EXPECT_EQ(context.error().code, ErrorCode::NoGlContext);
    EXPECT_TRUE(contains(context.error().detail, "SLUICE_EGL_PLATFORM")) << context.error().detail;
    EXPECT_TRUE(contains(context.error().detail, "'no-such-platform'"));
}

TEST(HeadlessContext, OptionsPlatformOverridesTheEnvironment) {
    ScopedEnv env("SLUICE_EGL_PLATFORM", "no-such-platform");
    ContextOptions options;
    options.platform = "auto";
    auto context = Context::createHeadless(options);
    ASSERT_TRUE(context) << context.error().message();
}

// True on every machine: the device platform either gives a working context (NVIDIA; Mesa's
// software device) or a NoGlContext that names only device attempts, never a fallback.
TEST(HeadlessContext, ForcedDevicePlatformRunsOnAnEglDeviceOrSaysWhyNot) {
    ContextOptions options;
    options.platform = "device";
    auto context = Context::createHeadless(options);
    if (context) {
        EXPECT_EQ(context->info().platform, "device");
        EXPECT_GE(context->info().deviceIndex, 0);
        std::printf("device platform: device %d (%s), %s\n", context->info().deviceIndex,
                    context->info().deviceName.c_str(), context->info().renderer.c_str());
        auto selfTest = context->selfTest();
        EXPECT_TRUE(selfTest) << selfTest.error().message();
    } else {
        EXPECT_EQ(context.error().code, ErrorCode::NoGlContext);
        EXPECT_TRUE(contains(context.error().detail, "device")) << context.error().detail;
        EXPECT_FALSE(contains(context.error().detail, "surfaceless platform:"));
    }
}

TEST(HeadlessContext, ForcedSurfacelessPlatformRunsOnMesaOrSaysWhyNot) {
    ContextOptions options;
    options.platform = "surfaceless";
    auto context = Context::createHeadless(options);
    if (context) {
        EXPECT_EQ(context->info().platform, "surfaceless");
        EXPECT_EQ(context->info().deviceIndex, -1);
        auto selfTest = context->selfTest();
        EXPECT_TRUE(selfTest) << selfTest.error().message();
    } else {
        EXPECT_EQ(context.error().code, ErrorCode::NoGlContext);
        EXPECT_TRUE(contains(context.error().detail, "surfaceless platform:"))
            << context.error().detail;
        EXPECT_FALSE(contains(context.error().detail, "device 0"));
    }
}

TEST(HeadlessContext, RejectsAnOutOfRangeDeviceIndexWithoutFallingBack) {
    ContextOptions options;
    options.deviceIndex = 999;
    auto context = Context::createHeadless(options);
    ASSERT_FALSE(context);
    EXPECT_EQ(context.error().code, ErrorCode::NoGlContext);
    const std::string& detail = context.error().detail;
    EXPECT_TRUE(contains(detail, "device index 999 out of range") ||
                contains(detail, "lacks EGL_EXT_platform_device"))
        << detail;
    EXPECT_FALSE(contains(detail, "surfaceless platform:")) << detail;
}

TEST(HeadlessContext, CreatesASecondContextAfterTheFirstIsDestroyed) {
    std::string firstRenderer;
    for (int round = 0; round < 2; ++round) {
        auto context = Context::createHeadless();
        ASSERT_TRUE(context) << "round " << round << ": " << context.error().message();
        auto selfTest = context->selfTest(1000);
        EXPECT_TRUE(selfTest) << "round " << round << ": " << selfTest.error().message();
        if (round == 0)
            firstRenderer = context->info().renderer;
        else
            EXPECT_EQ(context->info().renderer, firstRenderer);
    }
}

TEST(HeadlessContext, KeepsAnotherLiveContextWorkingWhenOneIsDestroyed) {
    auto first = Context::createHeadless();
    ASSERT_TRUE(first) << first.error().message();
    {
        auto second = Context::createHeadless();
        ASSERT_TRUE(second) << second.error().message();
        auto selfTest = second->selfTest(1000);
        EXPECT_TRUE(selfTest) << selfTest.error().message();
    }
    // Both may share one EGL display: destroying the second must not terminate it.
    auto selfTest = first->selfTest(1000);
    EXPECT_TRUE(selfTest) << selfTest.error().message();
}

TEST(HeadlessContext, MovedContextKeepsWorkingAndTheSourceReleasesNothing) {
    auto created = Context::createHeadless();
    ASSERT_TRUE(created) << created.error().message();
    Context moved(std::move(*created));
    Context assigned = std::move(moved);
    auto selfTest = assigned.selfTest(1000);
    EXPECT_TRUE(selfTest) << selfTest.error().message();
    EXPECT_THROW(moved.makeCurrent(), std::runtime_error); // NOLINT(bugprone-use-after-move)
}

TEST(HeadlessContext, EmbeddedSelfTestSourceHasItsSharedHeadersInlined) {
    const std::string_view source = shaders::shaderSource("gpu_selftest.comp");
    ASSERT_FALSE(source.empty());
    EXPECT_NE(source.find("struct SelfTestParams"), std::string_view::npos);
    EXPECT_NE(source.find("SLUICE_GROUP_OFFSET_UNIFORM"), std::string_view::npos);
    // Quoted includes are inlined; only the C++-only <...> includes of GlslBridge.h remain.
    EXPECT_EQ(source.find("#include \""), std::string_view::npos);
    EXPECT_TRUE(shaders::shaderSource("no_such_shader.comp").empty());
}

using EmbeddedSelfTest = test::GpuTest;

TEST_F(EmbeddedSelfTest, MatchesTheSharedCpuFormulaOver100kValues) {
    auto result = context().selfTest(100000);
    EXPECT_TRUE(result) << result.error().message();
}

TEST_F(EmbeddedSelfTest, MatchesTheCpuWhenSplitIntoChunkedDispatches) {
    auto result = context().selfTest(100000, 7);
    EXPECT_TRUE(result) << result.error().message();
}

/// Makes an invalid GL call: binding index far beyond GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS.
void provokeGlError(const Buffer& buffer) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1u << 20, buffer.id());
}

TEST(DebugOutput, CollectPolicyRecordsGlErrorsForTheCaller) {
    ContextOptions options;
    options.debug = true;
    options.debugPolicy = DebugPolicy::Collect;
    auto context = Context::createHeadless(options);
    ASSERT_TRUE(context) << context.error().message();
    EXPECT_TRUE(context->info().debug);
    auto buffer = Buffer::create(16);
    ASSERT_TRUE(buffer) << buffer.error().message();

    provokeGlError(*buffer);
    buffer->upload(std::array<float, 4>{1, 2, 3, 4}); // Collect: library calls do not fail
    auto messages = context->takeDebugMessages();
    ASSERT_FALSE(messages.empty());
    EXPECT_TRUE(messages[0].isError());
    EXPECT_EQ(messages[0].type, static_cast<GLenum>(GL_DEBUG_TYPE_ERROR));
    EXPECT_TRUE(contains(messages[0].describe(), "GL error")) << messages[0].describe();
    EXPECT_TRUE(context->takeDebugMessages().empty());
}

TEST(DebugOutput, AssertPolicyFailsTheNextLibraryCall) {
    ContextOptions options;
    options.debug = true;
    auto context = Context::createHeadless(options);
    ASSERT_TRUE(context) << context.error().message();
    auto buffer = Buffer::create(16);
    ASSERT_TRUE(buffer) << buffer.error().message();
    buffer->upload(std::array<float, 4>{1, 2, 3, 4});

    provokeGlError(*buffer);
    EXPECT_THROW(buffer->upload(std::array<float, 4>{1, 2, 3, 4}), std::runtime_error);
    context->assertNoDebugErrors(); // the failed check drained them
}

TEST(DebugOutput, AssertNoDebugErrorsFailsOnARecordedError) {
    ContextOptions options;
    options.debug = true;
    options.debugPolicy = DebugPolicy::Collect;
    auto context = Context::createHeadless(options);
    ASSERT_TRUE(context) << context.error().message();
    auto buffer = Buffer::create(16);
    ASSERT_TRUE(buffer) << buffer.error().message();
    context->assertNoDebugErrors();

    provokeGlError(*buffer);
    EXPECT_THROW(context->assertNoDebugErrors(), std::runtime_error);
}

} // namespace
} // namespace sluice::gpu
