// sluice-play reports every mode's failures (benchmark included) through the one mapping of
// sluice/format/ExitCodes.h.
#include <gtest/gtest.h>

#include "sluice/rt/play/PlayCli.h"

namespace sluice::rt {
namespace {

TEST(PlayExitCode, ShaderFailuresAreInternalErrorsInEveryMode) {
    EXPECT_EQ(reportFailure({ErrorCode::ShaderCompile, "log"}), kExitInternal);
}

TEST(PlayExitCode, NoContextIsThreeAndBadInputTwo) {
    EXPECT_EQ(reportFailure({ErrorCode::NoGlContext, "no EGL"}), kExitNoGlContext);
    EXPECT_EQ(reportFailure({ErrorCode::InvalidArgument, "--size 0x0"}), kExitBadInput);
    EXPECT_EQ(reportFailure({ErrorCode::Io, "cannot write"}), kExitBadInput);
}

TEST(PlayExitCode, ReportFailurePrintsTheMessageOnStderr) {
    ::testing::internal::CaptureStderr();
    (void)reportFailure({ErrorCode::Io, "out/s.json: cannot write"});
    EXPECT_EQ(::testing::internal::GetCapturedStderr(),
              "sluice-play: out/s.json: cannot write [Io]\n");
}

} // namespace
} // namespace sluice::rt
