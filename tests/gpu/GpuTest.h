// Test fixture for GPU tests: a debug context that fails loudly, checked again after each test.
#pragma once

#include <optional>
#include <string>

#include <dlfcn.h>
#include <link.h>

#include <gtest/gtest.h>

#include "sluice/gpu/Context.h"

namespace sluice::gpu::test {

/// Creates a headless debug context (DebugPolicy::Assert) per test, so any GL error during the
/// test fails it; TearDown fails the test on errors no library call checked.
/// Mesa unloads its GL driver (*_dri.so) with the last context; under ASan, LeakSanitizer then
/// reports the caches the driver filled (and still references from its static data) as leaks
/// when the process exits. Every GPU test binary keeps the driver mapped for its whole life
/// (as RenderTestSupport.h does for the programs the render tests start), so every other
/// allocation is still checked. Harmless without ASan.
class KeepGlDriverLoaded : public ::testing::Environment {
public:
    void SetUp() override {
        auto context = Context::createHeadless();
        if (!context)
            return; // the tests report it themselves
        dl_iterate_phdr(
            [](dl_phdr_info* info, std::size_t, void*) {
                const std::string name = info->dlpi_name != nullptr ? info->dlpi_name : "";
                if (name.find("_dri.so") != std::string::npos)
                    dlopen(name.c_str(), RTLD_NOW | RTLD_NODELETE);
                return 0;
            },
            nullptr);
    }
};

/// Registered once per test binary (an inline variable has one instance per program).
inline ::testing::Environment* const kKeepGlDriverLoaded =
    ::testing::AddGlobalTestEnvironment(new KeepGlDriverLoaded);

class GpuTest : public ::testing::Test {
protected:
    void SetUp() override {
        ContextOptions options;
        options.debug = true;
        auto context = Context::createHeadless(options);
        ASSERT_TRUE(context) << context.error().message();
        m_context.emplace(std::move(*context));
    }

    void TearDown() override {
        if (m_context)
            m_context->assertNoDebugErrors();
        m_context.reset();
    }

    Context& context() { return *m_context; }

private:
    std::optional<Context> m_context;
};

} // namespace sluice::gpu::test
