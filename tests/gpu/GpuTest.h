// Test fixture for GPU tests: a debug context that fails loudly, checked again after each test.
#pragma once

#include <optional>

#include <gtest/gtest.h>

#include "sluice/gpu/Context.h"

namespace sluice::gpu::test {

/// Creates a headless debug context (DebugPolicy::Assert) per test, so any GL error during the
/// test fails it; TearDown fails the test on errors no library call checked.
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
