// The one mapping from errors to exit codes that both programs use (sluice/format/ExitCodes.h):
// a mesh too large for the GPU is bad input (2), not an internal error (4). The GPU-memory path
// itself needs a driver that reports free memory.
#include <gtest/gtest.h>

#include "sluice/format/support/ExitCodes.h"

namespace sluice {
namespace {

TEST(ExitCodes, AMeshOrGridTooLargeForTheGpuIsBadInput) {
    EXPECT_EQ(exitCodeFor({ErrorCode::GpuOutOfMemory, "needs 20 GiB, 8 are free"}), kExitBadInput);
    EXPECT_EQ(exitCodeFor({ErrorCode::SizeOverflow, "over the largest storage buffer"}),
              kExitBadInput);
}

TEST(ExitCodes, EveryInputErrorIsTwoNoContextThreeAndOurShadersFour) {
    for (const ErrorCode code :
         {ErrorCode::Io, ErrorCode::Truncated, ErrorCode::BadMagic, ErrorCode::UnsupportedVersion,
          ErrorCode::BadHeader, ErrorCode::SizeMismatch, ErrorCode::SizeOverflow,
          ErrorCode::OffsetOutOfRange, ErrorCode::ChecksumMismatch, ErrorCode::BadMetadata,
          ErrorCode::NonFinite, ErrorCode::InvalidArgument, ErrorCode::MeshImport,
          ErrorCode::EmptyMesh, ErrorCode::GpuOutOfMemory, ErrorCode::Unsupported})
        EXPECT_EQ(exitCodeFor({code, ""}), kExitBadInput) << errorCodeName(code);
    EXPECT_EQ(exitCodeFor({ErrorCode::NoGlContext, ""}), kExitNoGlContext);
    EXPECT_EQ(exitCodeFor({ErrorCode::ShaderCompile, ""}), kExitInternal);
    EXPECT_EQ(exitCodeFor({ErrorCode::ShaderLink, ""}), kExitInternal);
}

} // namespace
} // namespace sluice
