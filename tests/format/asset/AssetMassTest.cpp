// Mass properties in the asset metadata (format 1.1 on): layout, round trip and hostile values.
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "asset/AssetTestUtil.h"
#include "support/TempDir.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::test {
namespace {

using namespace sluice::format;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// [bytes] the meshMass block (1.1): the presence flag and 13 doubles.
constexpr std::size_t kMassBytes = 1 + 13 * 8;
/// [bytes] the fields 1.2 appends after meshMass: u8 layout, f64 bandWidth.
constexpr std::size_t kLayoutBytes = 1 + 8;
/// [bytes] the fields 1.3 appends after those, without volume maps: u64 samples' size, u32 count.
constexpr std::size_t kSplitBytes = 8 + 4;

/// Offset in the file of the meshMass block of a current-version file that has one (and no
/// volume map).
std::size_t massAt(std::span<const std::byte> bytes) {
    const AssetHeader h = headerOf(bytes);
    return std::size_t(h.metaOffset + h.metaSize) - kSplitBytes - kLayoutBytes - kMassBytes;
}

/// Offset in the file of the meshMass double number `n` (0 volume, 1-3 centre, 4-12 inertia
/// row by row).
std::size_t massDoubleAt(std::span<const std::byte> bytes, std::size_t n) {
    return massAt(bytes) + 1 + 8 * n;
}

/// makeAsset's file with the double `n` of its meshMass replaced by `value`, checksum repaired.
std::vector<std::byte> withMassDouble(std::size_t n, double value) {
    auto bytes = encodeOk(makeAsset());
    poke<double>(bytes, massDoubleAt(bytes, n), value);
    reseal(bytes);
    return bytes;
}

/// The detail of a decode that must fail with BadMetadata (empty if it did not).
std::string badMetadataDetail(std::span<const std::byte> bytes) {
    auto r = decodeAsset(bytes, "mass.slc");
    if (r.ok()) {
        ADD_FAILURE() << "accepted";
        return {};
    }
    EXPECT_EQ(r.error().code, ErrorCode::BadMetadata) << r.error().message();
    return r.error().detail;
}

TEST(AssetMass, IsStoredAfterTheVersion1_0FieldsAsAFlagAndThirteenDoubles) {
    const ColliderAsset with = makeAsset();
    ColliderAsset without = with;
    without.meta.meshMass.reset();
    const auto a = encodeOk(with);
    const auto b = encodeOk(without);
    EXPECT_EQ(headerOf(a).minor, kAssetMinor);
    EXPECT_EQ(headerOf(a).metaSize, headerOf(b).metaSize + 13 * 8);
    // Without: the flag 0, then only the 1.2 fields (layout 0 = dense, band width 0), then the
    // 1.3 split.
    const std::size_t bEnd =
        std::size_t(headerOf(b).metaOffset + headerOf(b).metaSize) - kSplitBytes;
    EXPECT_EQ(peek<std::uint8_t>(b, bEnd - kLayoutBytes - 1), 0u);
    EXPECT_EQ(peek<std::uint8_t>(b, bEnd - kLayoutBytes), 0u);
    EXPECT_EQ(peek<double>(b, bEnd - 8), 0.0);
    // With: flag 1, volume, centre, then the inertia tensor row by row.
    const MassProperties& m = *with.meta.meshMass;
    EXPECT_EQ(peek<std::uint8_t>(a, massAt(a)), 1u);
    EXPECT_EQ(peek<double>(a, massDoubleAt(a, 0)), m.volume);
    for (int i = 0; i < 3; ++i)
        EXPECT_EQ(peek<double>(a, massDoubleAt(a, 1 + std::size_t(i))), m.centerOfMass[i]);
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
            EXPECT_EQ(peek<double>(a, massDoubleAt(a, 4 + std::size_t(3 * row + col))),
                      m.inertia[col][row]);
}

TEST(AssetMass, SurvivesWriteAndReadBitForBitAndAbsenceStaysAbsent) {
    TempDir dir;
    ColliderAsset asset = makeAsset({4, 5, 3});
    // A tensor asymmetric within the reader's tolerance: shows the elements are not mirrored.
    asset.meta.meshMass->inertia[0][1] *= 1.0 + 1e-12;
    ASSERT_TRUE(writeAsset(dir / "with.slc", asset).ok());
    auto read = readAsset(dir / "with.slc");
    ASSERT_TRUE(read.ok()) << read.error().message();
    ASSERT_TRUE(read->meta.meshMass.has_value());
    EXPECT_EQ(read->meta.meshMass->volume, asset.meta.meshMass->volume);
    EXPECT_EQ(read->meta.meshMass->centerOfMass, asset.meta.meshMass->centerOfMass);
    EXPECT_EQ(read->meta.meshMass->inertia, asset.meta.meshMass->inertia);

    asset.meta.meshMass.reset();
    ASSERT_TRUE(writeAsset(dir / "without.slc", asset).ok());
    read = readAsset(dir / "without.slc");
    ASSERT_TRUE(read.ok()) << read.error().message();
    EXPECT_FALSE(read->meta.meshMass.has_value());
}

TEST(AssetMass, RejectsAPresenceFlagOtherThanZeroOrOne) {
    for (const std::uint8_t flag : {2, 0x80, 0xFF}) {
        auto bytes = encodeOk(makeAsset());
        poke<std::uint8_t>(bytes, massAt(bytes), flag);
        reseal(bytes);
        EXPECT_NE(badMetadataDetail(bytes).find("meshMass"), std::string::npos) << int(flag);
    }
    // A flag of 0 leaves bytes over: the 13 doubles are read as the 1.2 fields and what follows.
    auto bytes = encodeOk(makeAsset());
    poke<std::uint8_t>(bytes, massAt(bytes), 0);
    poke<double>(bytes, massDoubleAt(bytes, 0), 0.0); // its first byte read as layout: dense
    reseal(bytes);
    EXPECT_NE(badMetadataDetail(bytes).find("unexpected bytes"), std::string::npos);
}

TEST(AssetMass, RejectsANonFiniteValueAsBadMetadataNamingTheField) {
    for (const double value : {kNaN, kInf, -kInf}) {
        EXPECT_NE(badMetadataDetail(withMassDouble(0, value)).find("meshMass.volume"),
                  std::string::npos);
        for (std::size_t n = 1; n <= 3; ++n)
            EXPECT_NE(badMetadataDetail(withMassDouble(n, value)).find("meshMass.centerOfMass"),
                      std::string::npos)
                << "double " << n;
        for (std::size_t n = 4; n <= 12; ++n)
            EXPECT_NE(badMetadataDetail(withMassDouble(n, value)).find("meshMass.inertia"),
                      std::string::npos)
                << "double " << n;
    }
}

TEST(AssetMass, RejectsAVolumeThatIsNotPositive) {
    for (const double volume : {0.0, -0.0, -1.0, -1e-300})
        EXPECT_NE(badMetadataDetail(withMassDouble(0, volume)).find("meshMass.volume"),
                  std::string::npos)
            << volume;
}

TEST(AssetMass, RejectsAnAsymmetricInertiaButNotRounding) {
    const double i01 = makeAsset().meta.meshMass->inertia[1][0]; // row 0, column 1
    ASSERT_NE(i01, 0.0);
    // Element (0, 1) is double 4 + 1; (2, 1) is double 4 + 7.
    for (const std::size_t n : {std::size_t(5), std::size_t(11)}) {
        const std::string detail = badMetadataDetail(withMassDouble(n, 2.0 * i01 + 1e-3));
        EXPECT_NE(detail.find("meshMass.inertia is not symmetric"), std::string::npos) << detail;
    }
    // 1e-12 of the largest element off is rounding, not asymmetry.
    const double largest = makeAsset().meta.meshMass->inertia[0][0];
    auto r = decodeAsset(withMassDouble(5, i01 + 1e-12 * largest), "rounded.slc");
    EXPECT_TRUE(r.ok()) << r.error().message();
}

TEST(AssetWriter, RefusesMassPropertiesTheReaderWouldReject) {
    auto codeOf = [](const ColliderAsset& a) {
        auto r = encodeAsset(a);
        return r.ok() ? std::optional<ErrorCode>{} : std::optional(r.error().code);
    };
    ColliderAsset a = makeAsset();
    a.meta.meshMass->volume = kNaN;
    EXPECT_EQ(codeOf(a), ErrorCode::NonFinite);
    a = makeAsset();
    a.meta.meshMass->centerOfMass.z = kInf;
    EXPECT_EQ(codeOf(a), ErrorCode::NonFinite);
    a = makeAsset();
    a.meta.meshMass->volume = -2.0;
    EXPECT_EQ(codeOf(a), ErrorCode::InvalidArgument);
    a = makeAsset();
    a.meta.meshMass->inertia[2][0] += 1.0;
    EXPECT_EQ(codeOf(a), ErrorCode::InvalidArgument);
    a = makeAsset();
    EXPECT_EQ(codeOf(a), std::nullopt);
}

} // namespace
} // namespace sluice::test
