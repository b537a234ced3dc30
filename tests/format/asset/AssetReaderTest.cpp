// The asset reader against hostile files: truncation, every header field, metadata and payload.
#include <bit>
#include <cstring>
#include <limits>
#include <optional>

#include <gtest/gtest.h>

#include "asset/AllocationProbe.h"
#include "asset/AssetTestUtil.h"
#include "support/TempDir.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/support/AtomicFile.h"
#include "sluice/format/asset/Half.h"

namespace sluice::test {
namespace {

using namespace sluice::format;
namespace ho = header_offset;

constexpr std::size_t kSmallAllocation = 1u << 20; // [bytes] far below any hostile size here

std::vector<std::byte> smallFile(Storage storage = Storage::F32) {
    return encodeOk(makeAsset({3, 3, 3}, storage));
}

TEST(AssetReader, AcceptsAnUntouchedFile) {
    const auto bytes = smallFile();
    auto r = decodeAsset(bytes, "ok.sdf");
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_EQ(r->pointCount(), 27u);
}

TEST(AssetReader, RejectsEveryTruncatedPrefix) {
    for (const Storage storage : {Storage::F32, Storage::F16}) {
        const auto bytes = smallFile(storage);
        for (std::size_t len = 0; len < bytes.size(); ++len)
            EXPECT_EQ(decodeError(std::span(bytes).first(len)), ErrorCode::Truncated)
                << "prefix of " << len << " of " << bytes.size() << " bytes";
    }
}

TEST(AssetReader, RejectsTrailingBytes) {
    auto bytes = smallFile();
    bytes.push_back(std::byte{0});
    EXPECT_EQ(decodeError(bytes), ErrorCode::SizeMismatch);
}

TEST(AssetReader, RejectsEveryCorruptedMagicByte) {
    for (std::size_t i = 0; i < kAssetMagic.size(); ++i) {
        auto bytes = smallFile();
        bytes[ho::kMagic + i] ^= std::byte{0x20};
        EXPECT_EQ(decodeError(bytes), ErrorCode::BadMagic) << "magic byte " << i;
    }
}

TEST(AssetReader, RejectsAnotherMajorVersion) {
    for (const std::uint16_t major : {0, 2, 0xFFFF}) {
        auto bytes = smallFile();
        poke<std::uint16_t>(bytes, ho::kMajor, major);
        EXPECT_EQ(decodeError(bytes), ErrorCode::UnsupportedVersion) << "major " << major;
    }
}

TEST(AssetReader, RejectsANewerMinorVersion) {
    auto bytes = smallFile();
    poke<std::uint16_t>(bytes, ho::kMinor, kAssetMinor + 1);
    EXPECT_EQ(decodeError(bytes), ErrorCode::UnsupportedVersion);
}

TEST(AssetReader, LoadsTheCommittedVersion1_0FileWithNoMeshMass) {
    // data/asset-v1.0.slc was written by the format 1.0 writer from makeAsset({3, 4, 5}) as it
    // was then (every field but meshMass, which 1.0 does not have). Never regenerate it.
    const auto path = std::filesystem::path(SLUICE_SOURCE_DIR) / "tests/format/data/asset-v1.0.slc";
    auto bytes = readFileBytes(path, kMaxAssetFileBytes);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message();
    ASSERT_EQ(headerOf(*bytes).minor, 0u);
    auto r = readAsset(path);
    ASSERT_TRUE(r.ok()) << r.error().message();
    const ColliderAsset expected = makeAsset({3, 4, 5});
    EXPECT_EQ(r->meta.dims, expected.meta.dims);
    EXPECT_EQ(r->meta.origin, expected.meta.origin);
    EXPECT_EQ(r->meta.voxelSize, expected.meta.voxelSize);
    EXPECT_EQ(r->meta.sourceFile, expected.meta.sourceFile);
    EXPECT_EQ(r->meta.bake.signUsed, expected.meta.bake.signUsed);
    EXPECT_EQ(r->meta.toolVersion, expected.meta.toolVersion);
    EXPECT_EQ(r->meta.mesh.boundaryEdges, expected.meta.mesh.boundaryEdges);
    EXPECT_EQ(r->meta.validation.eikonalOutsideShare, expected.meta.validation.eikonalOutsideShare);
    EXPECT_EQ(r->distances, expected.distances);
    EXPECT_FALSE(r->meta.meshMass.has_value());
    // Re-written, it becomes a current file that reads back the same.
    auto again = decodeAsset(encodeOk(*r), "rewritten.slc");
    ASSERT_TRUE(again.ok()) << again.error().message();
    EXPECT_FALSE(again->meta.meshMass.has_value());
    EXPECT_EQ(again->distances, expected.distances);
}

TEST(AssetReader, LoadsTheCommittedVersion1_1FileWithMeshMassAsDense) {
    // data/asset-v1.1.slc was written by the format 1.1 writer from makeAsset({3, 4, 5}) as it
    // was then (meshMass, no layout or band width: 1.1 files are dense). Never regenerate it.
    const auto path = std::filesystem::path(SLUICE_SOURCE_DIR) / "tests/format/data/asset-v1.1.slc";
    auto bytes = readFileBytes(path, kMaxAssetFileBytes);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message();
    ASSERT_EQ(headerOf(*bytes).minor, kAssetMinorMeshMass);
    auto r = readAsset(path);
    ASSERT_TRUE(r.ok()) << r.error().message();
    const ColliderAsset expected = makeAsset({3, 4, 5});
    EXPECT_EQ(r->meta.dims, expected.meta.dims);
    EXPECT_EQ(r->meta.sourceFile, expected.meta.sourceFile);
    EXPECT_EQ(r->meta.validation.eikonalOutsideShare, expected.meta.validation.eikonalOutsideShare);
    EXPECT_EQ(r->distances, expected.distances);
    EXPECT_EQ(r->meta.layout, Layout::Dense);
    EXPECT_EQ(r->meta.bandWidth, 0.0);
    ASSERT_TRUE(r->meta.meshMass.has_value());
    EXPECT_EQ(r->meta.meshMass->volume, expected.meta.meshMass->volume);
    EXPECT_EQ(r->meta.meshMass->centerOfMass, expected.meta.meshMass->centerOfMass);
    EXPECT_EQ(r->meta.meshMass->inertia, expected.meta.meshMass->inertia);
    // Re-written, it becomes a current file: the same fields, the 1.2 ones at their defaults (a
    // layout byte and a band width) and the 1.3 split (the samples' size and no volume map).
    const auto rewritten = encodeOk(*r);
    EXPECT_EQ(headerOf(rewritten).minor, kAssetMinor);
    EXPECT_EQ(headerOf(rewritten).metaSize, headerOf(*bytes).metaSize + 1 + 8 + 8 + 4);
    auto again = decodeAsset(rewritten, "rewritten.slc");
    ASSERT_TRUE(again.ok()) << again.error().message();
    ASSERT_TRUE(again->meta.meshMass.has_value());
    EXPECT_EQ(again->meta.meshMass->inertia, expected.meta.meshMass->inertia);
    EXPECT_EQ(again->meta.layout, Layout::Dense);
    EXPECT_EQ(again->distances, expected.distances);
}

TEST(AssetReader, RejectsAFileLabelledWithAnotherMinorThanItsFieldsAsBadMetadata) {
    // The header is not under the checksum; the metadata decoder notices: read as 1.0 or 1.1, a
    // 1.2 block has bytes left over, and an older block read as a newer minor ends early (a 1.0
    // block before its meshMass flag, a 1.1 block before its layout).
    for (std::uint16_t minor = 0; minor < kAssetMinor; ++minor) {
        auto current = smallFile();
        poke<std::uint16_t>(current, ho::kMinor, minor);
        auto r = decodeAsset(current, "relabelled.slc");
        ASSERT_FALSE(r.ok()) << "minor " << minor;
        EXPECT_EQ(r.error().code, ErrorCode::BadMetadata);
        EXPECT_NE(r.error().detail.find("unexpected bytes after the last field"), std::string::npos)
            << r.error().detail;
    }

    struct Relabel {
        const char* file;
        std::uint16_t minor;
    };
    for (const Relabel& relabel : {Relabel{"asset-v1.0.slc", kAssetMinorMeshMass},
                                   Relabel{"asset-v1.0.slc", kAssetMinorSparse},
                                   Relabel{"asset-v1.1.slc", kAssetMinorSparse}}) {
        const auto path =
            std::filesystem::path(SLUICE_SOURCE_DIR) / "tests/format/data" / relabel.file;
        auto old = readFileBytes(path, kMaxAssetFileBytes);
        ASSERT_TRUE(old.ok()) << old.error().message();
        poke<std::uint16_t>(*old, ho::kMinor, relabel.minor);
        auto r = decodeAsset(*old, "relabelled.slc");
        ASSERT_FALSE(r.ok()) << relabel.file << " as minor " << relabel.minor;
        EXPECT_EQ(r.error().code, ErrorCode::BadMetadata);
        EXPECT_NE(r.error().detail.find("ends early"), std::string::npos) << r.error().detail;
    }
}

TEST(AssetReader, RejectsAWrongHeaderSize) {
    for (const std::uint32_t size : {0u, 63u, 65u, 128u, 0xFFFFFFFFu}) {
        auto bytes = smallFile();
        poke<std::uint32_t>(bytes, ho::kHeaderSize, size);
        EXPECT_EQ(decodeError(bytes), ErrorCode::BadHeader) << "header size " << size;
    }
}

TEST(AssetReader, RejectsADeclaredFileSizeThatDiffersFromTheRealOne) {
    const auto good = smallFile();
    const std::uint64_t size = good.size();
    auto bytes = good;
    poke<std::uint64_t>(bytes, ho::kFileSize, size + 1);
    EXPECT_EQ(decodeError(bytes), ErrorCode::Truncated);
    poke<std::uint64_t>(bytes, ho::kFileSize, std::numeric_limits<std::uint64_t>::max());
    EXPECT_EQ(decodeError(bytes), ErrorCode::Truncated);
    poke<std::uint64_t>(bytes, ho::kFileSize, size - 1);
    EXPECT_EQ(decodeError(bytes), ErrorCode::SizeMismatch);
    poke<std::uint64_t>(bytes, ho::kFileSize, 0);
    EXPECT_EQ(decodeError(bytes), ErrorCode::SizeMismatch);
}

TEST(AssetReader, RejectsMetadataOffsetsOutsideOrOverlapping) {
    const auto good = smallFile();
    const AssetHeader h = headerOf(good);
    for (const std::uint64_t offset : {std::uint64_t(0), std::uint64_t(63), std::uint64_t(65),
                                       h.payloadOffset, h.fileSize + 1}) {
        auto bytes = good;
        poke<std::uint64_t>(bytes, ho::kMetaOffset, offset);
        EXPECT_EQ(decodeError(bytes), ErrorCode::OffsetOutOfRange) << "offset " << offset;
    }
    auto bytes = good;
    poke<std::uint64_t>(bytes, ho::kMetaOffset, std::numeric_limits<std::uint64_t>::max() - 3);
    EXPECT_EQ(decodeError(bytes), ErrorCode::SizeOverflow);
}

TEST(AssetReader, RejectsMetadataSizesThatOverflowOrOverlapThePayload) {
    const auto good = smallFile();
    const AssetHeader h = headerOf(good);
    auto bytes = good;
    poke<std::uint64_t>(bytes, ho::kMetaSize, std::numeric_limits<std::uint64_t>::max());
    EXPECT_EQ(decodeError(bytes), ErrorCode::SizeOverflow);
    poke<std::uint64_t>(bytes, ho::kMetaSize, kAssetMaxMetaBytes + 1);
    EXPECT_EQ(decodeError(bytes), ErrorCode::SizeOverflow);
    poke<std::uint64_t>(bytes, ho::kMetaSize, h.payloadOffset - h.metaOffset + 1);
    EXPECT_EQ(decodeError(bytes), ErrorCode::OffsetOutOfRange);
    // Shrunk past the alignment step: the payload no longer follows the metadata.
    poke<std::uint64_t>(bytes, ho::kMetaSize, h.metaSize - kAssetPayloadAlignment);
    EXPECT_EQ(decodeError(bytes), ErrorCode::OffsetOutOfRange);
}

TEST(AssetReader, RejectsPayloadOffsetsAndSizesOutsideOrOverlapping) {
    const auto good = smallFile();
    const AssetHeader h = headerOf(good);
    struct Case {
        std::size_t field;
        std::uint64_t value;
        ErrorCode code;
    };
    const std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
    const Case cases[] = {
        {ho::kPayloadOffset, h.payloadOffset + kAssetPayloadAlignment, ErrorCode::OffsetOutOfRange},
        {ho::kPayloadOffset, h.payloadOffset - kAssetPayloadAlignment, ErrorCode::OffsetOutOfRange},
        {ho::kPayloadOffset, 0, ErrorCode::OffsetOutOfRange},
        {ho::kPayloadOffset, kMax, ErrorCode::SizeOverflow},
        {ho::kPayloadSize, h.payloadSize + 4, ErrorCode::OffsetOutOfRange},
        {ho::kPayloadSize, h.payloadSize - 4, ErrorCode::OffsetOutOfRange},
        {ho::kPayloadSize, 0, ErrorCode::OffsetOutOfRange},
        {ho::kPayloadSize, kMax, ErrorCode::SizeOverflow},
    };
    for (const Case& c : cases) {
        auto bytes = good;
        poke<std::uint64_t>(bytes, c.field, c.value);
        EXPECT_EQ(decodeError(bytes), c.code) << "field at " << c.field << " = " << c.value;
    }
}

TEST(AssetReader, RejectsAWrongChecksum) {
    auto bytes = smallFile();
    bytes[ho::kChecksum] ^= std::byte{1};
    EXPECT_EQ(decodeError(bytes), ErrorCode::ChecksumMismatch);
}

TEST(AssetReader, RejectsEverySingleByteFlip) {
    for (const Storage storage : {Storage::F32, Storage::F16}) {
        const auto good = smallFile(storage);
        for (std::size_t i = 0; i < good.size(); ++i)
            for (const std::byte mask : {std::byte{0x01}, std::byte{0x80}, std::byte{0xFF}}) {
                auto bytes = good;
                bytes[i] ^= mask;
                EXPECT_FALSE(decodeAsset(bytes, "flip.sdf").ok())
                    << "byte " << i << " xor " << std::to_integer<int>(mask);
            }
    }
}

TEST(AssetReader, SurvivesEveryMetadataByteFlipBehindAValidChecksum) {
    // Past the checksum, the metadata decoder meets arbitrary bytes: it may accept a changed
    // value, but must not crash, assert or allocate from a damaged length.
    const auto good = smallFile();
    const AssetHeader h = headerOf(good);
    for (std::size_t i = h.metaOffset; i < h.metaOffset + h.metaSize; ++i)
        for (const std::byte mask : {std::byte{0x01}, std::byte{0x40}, std::byte{0xFF}}) {
            auto bytes = good;
            bytes[i] ^= mask;
            reseal(bytes);
            resetLargestAllocation();
            auto r = decodeAsset(bytes, "fuzz.sdf");
            EXPECT_LT(largestAllocation(), kSmallAllocation) << "byte " << i;
            if (!r.ok()) {
                EXPECT_TRUE(r.error().code == ErrorCode::BadMetadata ||
                            r.error().code == ErrorCode::NonFinite ||
                            r.error().code == ErrorCode::SizeOverflow ||
                            r.error().code == ErrorCode::SizeMismatch)
                    << "byte " << i << ": " << r.error().message();
            }
        }
}

TEST(AssetReader, RejectsHugeDimsWithoutAllocating) {
    const std::uint32_t kMax = std::numeric_limits<std::uint32_t>::max();
    const glm::uvec3 cases[] = {{kMax, kMax, kMax}, {1u << 16, 1u << 16, 2}, {1025, 1024, 256}};
    for (const glm::uvec3& dims : cases) {
        auto bytes = smallFile();
        for (int a = 0; a < 3; ++a)
            poke<std::uint32_t>(bytes, metaAt(bytes, meta_offset::kDims + 4 * a), dims[a]);
        reseal(bytes);
        resetLargestAllocation();
        EXPECT_EQ(decodeError(bytes), ErrorCode::SizeOverflow) << dims.x << "x" << dims.y;
        EXPECT_LT(largestAllocation(), kSmallAllocation);
    }
}

TEST(AssetReader, RejectsDimsBelowTwo) {
    for (int axis = 0; axis < 3; ++axis)
        for (const std::uint32_t d : {0u, 1u}) {
            auto bytes = smallFile();
            poke<std::uint32_t>(bytes, metaAt(bytes, meta_offset::kDims + 4 * axis), d);
            reseal(bytes);
            EXPECT_EQ(decodeError(bytes), ErrorCode::BadMetadata) << "axis " << axis;
        }
}

TEST(AssetReader, RejectsDimsThatDisagreeWithThePayloadSize) {
    auto bytes = smallFile(); // 3x3x3
    poke<std::uint32_t>(bytes, metaAt(bytes, meta_offset::kDims), 2u);
    reseal(bytes);
    EXPECT_EQ(decodeError(bytes), ErrorCode::SizeMismatch);
}

TEST(AssetReader, RejectsBadVoxelSizeAndOrigin) {
    const double kNaN = std::numeric_limits<double>::quiet_NaN();
    const double kInf = std::numeric_limits<double>::infinity();
    struct Case {
        std::size_t at;
        double value;
        ErrorCode code;
    };
    const Case cases[] = {
        {meta_offset::kVoxelSize, kNaN, ErrorCode::NonFinite},
        {meta_offset::kVoxelSize, kInf, ErrorCode::NonFinite},
        {meta_offset::kVoxelSize, 0.0, ErrorCode::BadMetadata},
        {meta_offset::kVoxelSize, -0.5, ErrorCode::BadMetadata},
        {meta_offset::kVoxelSize, 1.0e308, ErrorCode::NonFinite}, // far corner overflows
        {meta_offset::kOrigin, kNaN, ErrorCode::NonFinite},
        {meta_offset::kOrigin + 16, -kInf, ErrorCode::NonFinite},
    };
    for (const Case& c : cases) {
        auto bytes = smallFile();
        poke<double>(bytes, metaAt(bytes, c.at), c.value);
        reseal(bytes);
        EXPECT_EQ(decodeError(bytes), c.code) << "meta byte " << c.at << " = " << c.value;
    }
}

TEST(AssetReader, RejectsUnknownEnumValues) {
    auto bytes = smallFile();
    poke<std::uint8_t>(bytes, metaAt(bytes, meta_offset::kStorage), 2);
    reseal(bytes);
    EXPECT_EQ(decodeError(bytes), ErrorCode::BadMetadata);

    bytes = smallFile();
    poke<std::int8_t>(bytes, metaAt(bytes, meta_offset::kSignConvention), 0);
    reseal(bytes);
    EXPECT_EQ(decodeError(bytes), ErrorCode::BadMetadata);
}

TEST(AssetReader, RejectsABigEndianMetadataArchive) {
    auto bytes = smallFile();
    poke<std::uint8_t>(bytes, metaAt(bytes, meta_offset::kEndianFlag), 0);
    reseal(bytes);
    EXPECT_EQ(decodeError(bytes), ErrorCode::BadMetadata);
}

TEST(AssetReader, RejectsAHostileStringLengthWithoutAllocating) {
    const auto good = smallFile();
    const std::size_t lengthAt = metaAt(good, meta_offset::kSourceFile);
    ASSERT_EQ(peek<std::uint64_t>(good, lengthAt), std::string("bunny.obj").size());
    const std::uint64_t remaining = headerOf(good).metaSize - meta_offset::kSourceFile - 8;
    for (const std::uint64_t length :
         {std::uint64_t(1) << 40, std::numeric_limits<std::uint64_t>::max(), remaining + 1,
          std::uint64_t(kAssetMaxStringBytes + 1)}) {
        auto bytes = good;
        poke<std::uint64_t>(bytes, lengthAt, length);
        reseal(bytes);
        resetLargestAllocation();
        auto r = decodeAsset(bytes, "hostile.sdf");
        ASSERT_FALSE(r.ok()) << "length " << length;
        EXPECT_EQ(r.error().code, ErrorCode::BadMetadata) << "length " << length;
        EXPECT_LT(largestAllocation(), kSmallAllocation) << "length " << length;
        EXPECT_NE(r.error().detail.find("sourceFile"), std::string::npos) << r.error().detail;
    }
}

TEST(AssetReader, RejectsUnexpectedBytesAfterTheLastMetadataField) {
    const auto good = smallFile();
    std::vector<std::byte> meta(metaOf(good).begin(), metaOf(good).end());
    const auto payload = payloadOf(good);
    ASSERT_TRUE(decodeAsset(assemble(meta, payload), "reassembled.sdf").ok());
    meta.push_back(std::byte{0});
    EXPECT_EQ(decodeError(assemble(meta, payload)), ErrorCode::BadMetadata);
    meta.erase(meta.end() - 2, meta.end()); // a truncated last field
    EXPECT_EQ(decodeError(assemble(meta, payload)), ErrorCode::BadMetadata);
}

TEST(AssetReader, RejectsANaNSampleBehindAValidChecksum) {
    for (const Storage storage : {Storage::F32, Storage::F16}) {
        auto bytes = smallFile(storage);
        const AssetHeader h = headerOf(bytes);
        // Sample (1, 2, 0) = number 7.
        if (storage == Storage::F32)
            poke<std::uint32_t>(bytes, h.payloadOffset + 7 * 4, 0x7FC00000u);
        else
            poke<std::uint16_t>(bytes, h.payloadOffset + 7 * 2, 0x7E00u);
        reseal(bytes);
        auto r = decodeAsset(bytes, "nan.sdf");
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().code, ErrorCode::NonFinite);
        EXPECT_NE(r.error().detail.find("(1, 2, 0)"), std::string::npos) << r.error().detail;
    }
}

TEST(AssetReader, RejectsAnInfiniteSampleBehindAValidChecksum) {
    auto bytes = smallFile(Storage::F16);
    poke<std::uint16_t>(bytes, headerOf(bytes).payloadOffset, 0xFC00u); // -inf
    reseal(bytes);
    EXPECT_EQ(decodeError(bytes), ErrorCode::NonFinite);
}

TEST(AssetReader, MessagesNameTheFileAndTheRemedy) {
    auto bytes = smallFile();
    bytes.back() ^= std::byte{1};
    auto r = decodeAsset(bytes, "assets/bunny.sdf");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::ChecksumMismatch);
    EXPECT_NE(r.error().detail.find("assets/bunny.sdf"), std::string::npos);
    EXPECT_NE(r.error().detail.find("re-bake with sluice-bake"), std::string::npos);
}

TEST(AssetReader, ReadReportsMissingFilesAndFoldersAsIo) {
    TempDir dir;
    auto missing = readAsset(dir / "nothing.sdf");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::Io);
    auto folder = readAsset(dir.path());
    ASSERT_FALSE(folder.ok());
    EXPECT_EQ(folder.error().code, ErrorCode::Io);
}

TEST(AssetReader, ReadRejectsAnEmptyFileAsTruncated) {
    TempDir dir;
    ASSERT_TRUE(writeFileAtomic(dir / "empty.sdf", {}).ok());
    auto r = readAsset(dir / "empty.sdf");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::Truncated);
    EXPECT_NE(r.error().detail.find("empty.sdf"), std::string::npos);
}

} // namespace
} // namespace sluice::test
