// sluice-play's one mapping from errors to exit codes, used by every mode (benchmark included).
#include <gtest/gtest.h>

#include "sluice/rt/PlayCli.h"

namespace sluice::rt {
namespace {

TEST(PlayExitCode, ShaderFailuresAreInternalErrorsInEveryMode) {
    EXPECT_EQ(playExitCode({ErrorCode::ShaderCompile, "x"}), kPlayExitInternal);
    EXPECT_EQ(playExitCode({ErrorCode::ShaderLink, "x"}), kPlayExitInternal);
    EXPECT_EQ(reportFailure({ErrorCode::ShaderCompile, "log"}), kPlayExitInternal);
}

TEST(PlayExitCode, NoContextIsThreeAndBadInputTwo) {
    EXPECT_EQ(reportFailure({ErrorCode::NoGlContext, "no EGL"}), kPlayExitNoGlContext);
    EXPECT_EQ(reportFailure({ErrorCode::InvalidArgument, "--size 0x0"}), kPlayExitBadInput);
    EXPECT_EQ(reportFailure({ErrorCode::Io, "cannot write"}), kPlayExitBadInput);
}

TEST(PlayExitCode, ReportFailurePrintsTheMessageOnStderr) {
    ::testing::internal::CaptureStderr();
    (void)reportFailure({ErrorCode::Io, "out/s.json: cannot write"});
    EXPECT_EQ(::testing::internal::GetCapturedStderr(),
              "sluice-play: out/s.json: cannot write [Io]\n");
}

} // namespace
} // namespace sluice::rt
