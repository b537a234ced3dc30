// Hostile collider assets: every value of every header and metadata byte, each rejected with
// the error its field calls for, and no allocation larger than the file justifies.
// (tests/format/AssetReaderTest.cpp covers truncation, each field's chosen bad values and three
// flip masks per byte; this goes through all 255 other values of every byte.)
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "asset/AllocationProbe.h"
#include "asset/AssetTestUtil.h"
#include "ReliabilityTest.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::reliability {
namespace {

using namespace sluice::format;
using test::encodeOk;
using test::headerOf;
using test::makeAsset;
using test::reseal;
namespace ho = header_offset;

/// [bytes] the most a decode may allocate at once for a file of `size` bytes: the samples as
/// floats (twice an fp16 payload) plus a little for messages.
std::size_t justified(std::size_t size) {
    return 2 * size + 4096;
}

/// The error codes a change to the header byte at `offset` may give.
std::set<ErrorCode> codesForHeaderByte(std::size_t offset) {
    if (offset < ho::kMajor)
        return {ErrorCode::BadMagic};
    if (offset < ho::kHeaderSize)
        return {ErrorCode::UnsupportedVersion};
    if (offset < ho::kFileSize)
        return {ErrorCode::BadHeader};
    if (offset < ho::kMetaOffset)
        return {ErrorCode::Truncated, ErrorCode::SizeMismatch};
    // The checksum covers the body, not the header: a metadata size a few bytes off still lays
    // the sections out as version 1 requires (the payload offset rounds up to 16), and then the
    // metadata decoder finds the block ending early or bytes after its last field.
    if (offset >= ho::kMetaSize && offset < ho::kPayloadOffset)
        return {ErrorCode::OffsetOutOfRange, ErrorCode::SizeOverflow, ErrorCode::BadMetadata};
    if (offset < ho::kChecksum)
        return {ErrorCode::OffsetOutOfRange, ErrorCode::SizeOverflow};
    return {ErrorCode::ChecksumMismatch};
}

class HostileAsset : public ::testing::TestWithParam<Storage> {};

TEST_P(HostileAsset, EveryOtherValueOfEveryHeaderByteIsRejectedWithItsFieldsError) {
    const auto good = encodeOk(makeAsset({3, 4, 5}, GetParam()));
    std::map<ErrorCode, int> seen;
    for (std::size_t i = 0; i < kAssetHeaderSize; ++i) {
        const std::set<ErrorCode> allowed = codesForHeaderByte(i);
        for (int v = 0; v < 256; ++v) {
            if (std::byte(v) == good[i])
                continue;
            auto bytes = good;
            bytes[i] = std::byte(v);
            test::resetLargestAllocation();
            auto r = decodeAsset(bytes, "hostile.slc");
            EXPECT_LT(test::largestAllocation(), justified(bytes.size())) << "byte " << i;
            if (i >= ho::kMinor && i < ho::kHeaderSize &&
                test::peek<std::uint16_t>(bytes, ho::kMinor) < kAssetMinor &&
                test::peek<std::uint16_t>(bytes, ho::kMajor) == kAssetMajor) {
                // An older minor loads (AssetReaderTest reads a committed 1.0 file), but this
                // file's metadata has the current minor's fields: read as an older one, the
                // newer fields are left over.
                ASSERT_FALSE(r.ok()) << "byte " << i << " = " << v << " was accepted";
                EXPECT_EQ(r.error().code, ErrorCode::BadMetadata) << r.error().message();
                EXPECT_NE(r.error().detail.find("unexpected bytes after the last field"),
                          std::string::npos)
                    << r.error().detail;
                ++seen[r.error().code];
                continue;
            }
            ASSERT_FALSE(r.ok()) << "byte " << i << " = " << v << " was accepted";
            EXPECT_TRUE(allowed.count(r.error().code))
                << "byte " << i << " = " << v << ": " << r.error().message();
            EXPECT_EQ(r.error().detail.rfind("hostile.slc: ", 0), 0u) << r.error().detail;
            if (r.error().code == ErrorCode::BadMetadata) {
                const std::string& d = r.error().detail;
                EXPECT_TRUE(d.find("ends early") != std::string::npos ||
                            d.find("unexpected bytes after the last field") != std::string::npos)
                    << d;
            }
            ++seen[r.error().code];
        }
    }
    // Every header check was reached.
    for (const ErrorCode code :
         {ErrorCode::BadMagic, ErrorCode::UnsupportedVersion, ErrorCode::BadHeader,
          ErrorCode::Truncated, ErrorCode::SizeMismatch, ErrorCode::OffsetOutOfRange,
          ErrorCode::SizeOverflow, ErrorCode::ChecksumMismatch})
        EXPECT_GT(seen[code], 0) << errorCodeName(code);
}

// Calls f(i, v, bytes) with `good` changed in one metadata byte i to each value v it does not
// hold.
template <typename F> void forEveryOtherMetadataByte(const std::vector<std::byte>& good, F&& f) {
    const AssetHeader h = headerOf(good);
    for (std::size_t i = h.metaOffset; i < h.metaOffset + h.metaSize; ++i)
        for (int v = 0; v < 256; ++v) {
            if (std::byte(v) == good[i])
                continue;
            auto bytes = good;
            bytes[i] = std::byte(v);
            f(i, v, bytes);
        }
}

TEST_P(HostileAsset, EveryOtherValueOfEveryMetadataByteFailsTheChecksum) {
    const auto good = encodeOk(makeAsset({3, 4, 5}, GetParam()));
    forEveryOtherMetadataByte(good, [](std::size_t i, int v, std::vector<std::byte>& bytes) {
        auto r = decodeAsset(bytes, "hostile.slc");
        ASSERT_FALSE(r.ok()) << "metadata byte " << i << " = " << v;
        EXPECT_EQ(r.error().code, ErrorCode::ChecksumMismatch) << r.error().message();
    });
}

TEST_P(HostileAsset, EveryOtherValueOfEveryMetadataByteBehindAValidChecksumIsSafe) {
    // Past the checksum (a deliberate forgery, or a writer bug) the metadata decoder meets every
    // value of every byte: it may accept a changed value that is still valid, otherwise it says
    // which rule broke; it never allocates from a damaged length.
    const auto good = encodeOk(makeAsset({3, 4, 5}, GetParam()));
    const AssetHeader h = headerOf(good);
    std::map<ErrorCode, int> seen;
    int accepted = 0;
    forEveryOtherMetadataByte(good, [&](std::size_t i, int v, std::vector<std::byte>& bytes) {
        reseal(bytes);
        test::resetLargestAllocation();
        auto r = decodeAsset(bytes, "forged.slc");
        EXPECT_LT(test::largestAllocation(), justified(bytes.size()))
            << "metadata byte " << i - h.metaOffset << " = " << v;
        if (r.ok()) {
            ++accepted;
            // What is accepted is a consistent asset: the writer takes it back.
            EXPECT_TRUE(encodeAsset(*r).ok()) << "metadata byte " << i - h.metaOffset;
            return;
        }
        const ErrorCode code = r.error().code;
        EXPECT_TRUE(code == ErrorCode::BadMetadata || code == ErrorCode::NonFinite ||
                    code == ErrorCode::SizeOverflow || code == ErrorCode::SizeMismatch)
            << "metadata byte " << i - h.metaOffset << " = " << v << ": " << r.error().message();
        ++seen[code];
    });
    std::printf("%zu metadata bytes x 255 values: %d accepted, %d BadMetadata, %d NonFinite, "
                "%d SizeOverflow, %d SizeMismatch\n",
                std::size_t(h.metaSize), accepted, seen[ErrorCode::BadMetadata],
                seen[ErrorCode::NonFinite], seen[ErrorCode::SizeOverflow],
                seen[ErrorCode::SizeMismatch]);
    EXPECT_GT(seen[ErrorCode::BadMetadata], 0);
    EXPECT_GT(seen[ErrorCode::NonFinite], 0);
    EXPECT_GT(seen[ErrorCode::SizeMismatch], 0);
}

INSTANTIATE_TEST_SUITE_P(Storage, HostileAsset, ::testing::Values(Storage::F32, Storage::F16),
                         [](const auto& paramInfo) {
                             return std::string(storageName(paramInfo.param));
                         });

TEST(HostileAssetSizes, DimsClaimingTheLargestGridInATinyFileAllocateNothingBig) {
    // Dims whose product is at the limit, or overflows 32 and 64 bits, behind a valid checksum:
    // the payload size check answers before the samples are allocated.
    const std::uint32_t kMax = std::numeric_limits<std::uint32_t>::max();
    const glm::uvec3 cases[] = {{1u << 10, 1u << 9, 1u << 9}, // exactly kMaxAssetPoints
                                {kMax, kMax, kMax},
                                {1u << 16, 1u << 16, 1u << 16},
                                {645, 645, 645}};
    for (const glm::uvec3& dims : cases) {
        auto bytes = encodeOk(makeAsset({3, 3, 3}));
        for (int a = 0; a < 3; ++a)
            test::poke<std::uint32_t>(
                bytes, test::metaAt(bytes, meta_offset::kDims + 4 * std::size_t(a)), dims[a]);
        reseal(bytes);
        test::resetLargestAllocation();
        auto r = decodeAsset(bytes, "huge.slc");
        ASSERT_FALSE(r.ok());
        EXPECT_TRUE(r.error().code == ErrorCode::SizeOverflow ||
                    r.error().code == ErrorCode::SizeMismatch)
            << r.error().message();
        EXPECT_LT(test::largestAllocation(), justified(bytes.size()));
    }
}

TEST(HostileAssetSizes, AFileLargerThanTheLargestAssetIsRefusedBeforeReading) {
    // A sparse file one byte over kMaxAssetFileBytes: no disk space, and no read attempted.
    const fs::path dir = freshDir("hostile-asset-size");
    const fs::path path = dir / "huge.slc";
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::ftruncate(fd, off_t(kMaxAssetFileBytes + 1)), 0);
    ::close(fd);
    test::resetLargestAllocation();
    auto r = readAsset(path);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::SizeOverflow) << r.error().message();
    EXPECT_NE(r.error().detail.find("huge.slc"), std::string::npos);
    EXPECT_LT(test::largestAllocation(), std::size_t(1) << 20);
    fs::remove(path);
}

TEST(HostileAssetSizes, ALargeFileOfZerosIsRejectedByItsMagicAfterOneBoundedRead) {
    // Within the size limit, the reader reads the file (its size justifies that) and no more.
    const fs::path dir = freshDir("hostile-asset-zeros");
    const fs::path path = dir / "zeros.slc";
    const std::uint64_t size = std::uint64_t(64) << 20;
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::ftruncate(fd, off_t(size)), 0);
    ::close(fd);
    test::resetLargestAllocation();
    auto r = readAsset(path);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::BadMagic);
    EXPECT_LE(test::largestAllocation(), size + 4096);
    fs::remove(path);
}

} // namespace
} // namespace sluice::reliability
