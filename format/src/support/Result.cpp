// Names of error codes, and the assert handler behind SLUICE_ASSERT.
#include "sluice/format/support/Result.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace sluice {

std::string_view errorCodeName(ErrorCode code) {
    switch (code) {
    case ErrorCode::Io: return "Io";
    case ErrorCode::Truncated: return "Truncated";
    case ErrorCode::BadMagic: return "BadMagic";
    case ErrorCode::UnsupportedVersion: return "UnsupportedVersion";
    case ErrorCode::BadHeader: return "BadHeader";
    case ErrorCode::SizeMismatch: return "SizeMismatch";
    case ErrorCode::SizeOverflow: return "SizeOverflow";
    case ErrorCode::OffsetOutOfRange: return "OffsetOutOfRange";
    case ErrorCode::ChecksumMismatch: return "ChecksumMismatch";
    case ErrorCode::BadMetadata: return "BadMetadata";
    case ErrorCode::NonFinite: return "NonFinite";
    case ErrorCode::InvalidArgument: return "InvalidArgument";
    case ErrorCode::MeshImport: return "MeshImport";
    case ErrorCode::EmptyMesh: return "EmptyMesh";
    case ErrorCode::NoGlContext: return "NoGlContext";
    case ErrorCode::ShaderCompile: return "ShaderCompile";
    case ErrorCode::ShaderLink: return "ShaderLink";
    case ErrorCode::GpuOutOfMemory: return "GpuOutOfMemory";
    case ErrorCode::Unsupported: return "Unsupported";
    }
    return "Unknown";
}

namespace {
void defaultHandler(const char* expr, const char* msg, const char* file, int line) {
    std::fprintf(stderr, "%s:%d: assertion failed: %s (%s)\n", file, line, expr, msg);
}
std::atomic<AssertHandler> g_handler{&defaultHandler};
} // namespace

AssertHandler setAssertHandler(AssertHandler handler) {
    return g_handler.exchange(handler ? handler : &defaultHandler);
}

void assertFailed(const char* expr, const char* msg, const char* file, int line) {
    g_handler.load()(expr, msg, file, line);
    // A handler that returns (instead of throwing) still ends the program: the contract is broken.
    std::abort();
}

} // namespace sluice
