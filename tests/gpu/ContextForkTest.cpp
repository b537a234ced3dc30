// Contexts across fork(): a child forked with a context open fails at once instead of waiting
// for the parent's driver threads; one forked after the last context closed opens its own.
#include <cstdio>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "sluice/gpu/Context.h"

namespace sluice::gpu {
namespace {

/// Runs `child` in a fork()ed process, which SIGALRM ends after 60 s, and returns its exit code
/// (minus the signal's number if one ended it).
template <class F> int inForkedChild(F&& child) {
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::alarm(60);
        ::_exit(child());
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

TEST(ContextFork, AChildForkedWithAContextOpenFailsAtOnceAndDropsTheInheritedOne) {
    auto context = Context::createHeadless();
    ASSERT_TRUE(context) << context.error().message();
    const int code = inForkedChild([&] {
        if (!forkedFromGlProcess())
            return 10;
        const auto own = Context::createHeadless();
        if (own)
            return 11;
        if (own.error().code != ErrorCode::NoGlContext ||
            own.error().detail.find("spawn or forkserver") == std::string::npos)
            return 12;
        // Destroyed without an EGL call: eglTerminate would wait for the parent's threads.
        { const Context inherited = std::move(*context); }
        return 0;
    });
    EXPECT_EQ(code, 0) << "10: not marked as forked, 11: opened a context, 12: wrong error, "
                          "-14: hung until SIGALRM";
    EXPECT_FALSE(forkedFromGlProcess());
    const auto selfTest = context->selfTest(1000); // the parent's context is untouched
    EXPECT_TRUE(selfTest) << selfTest.error().message();
}

TEST(ContextFork, AChildForkedAfterTheLastContextClosedOpensItsOwn) {
    {
        const auto context = Context::createHeadless();
        ASSERT_TRUE(context) << context.error().message();
    }
    const int code = inForkedChild([] {
        if (forkedFromGlProcess())
            return 10;
        const auto own = Context::createHeadless();
        if (!own)
            return 11;
        return own->selfTest(1000) ? 0 : 12;
    });
    EXPECT_EQ(code, 0) << "10: marked as forked, 11: no context, 12: the self-test failed, "
                          "-14: hung until SIGALRM";
}

} // namespace
} // namespace sluice::gpu
