// fp16 conversion: exact on representable values, ties to even, saturation, subnormals.
#include <bit>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "sluice/format/asset/Half.h"

namespace sluice::test {
namespace {

using namespace sluice::format;

bool isNaNBits(std::uint16_t h) {
    return (h & 0x7C00u) == 0x7C00u && (h & 0x3FFu) != 0;
}

TEST(Half, KnownValuesConvertExactlyBothWays) {
    struct Case {
        float value;
        std::uint16_t bits;
    };
    const Case cases[] = {
        {0.0f, 0x0000},           {-0.0f, 0x8000},    {1.0f, 0x3C00},      {-2.0f, 0xC000},
        {0.5f, 0x3800},           {65504.0f, 0x7BFF}, {-65504.0f, 0xFBFF}, {0.099975586f, 0x2E66},
        {6.1035156e-05f, 0x0400}, // smallest normal, 2^-14
        {5.9604645e-08f, 0x0001}, // smallest subnormal, 2^-24
        {6.0975552e-05f, 0x03FF}, // largest subnormal
    };
    for (const Case& c : cases) {
        EXPECT_EQ(floatToHalf(c.value), c.bits) << c.value;
        EXPECT_EQ(std::bit_cast<std::uint32_t>(halfToFloat(c.bits)),
                  std::bit_cast<std::uint32_t>(c.value))
            << std::hex << c.bits;
    }
}

TEST(Half, EveryFiniteHalfSurvivesARoundTripThroughFloat) {
    for (std::uint32_t h = 0; h <= 0xFFFF; ++h) {
        const auto bits = std::uint16_t(h);
        if ((bits & 0x7C00u) == 0x7C00u)
            continue; // inf and NaN: below
        EXPECT_EQ(floatToHalf(halfToFloat(bits)), bits) << std::hex << h;
    }
}

TEST(Half, RoundsToNearestWithTiesToEven) {
    // For each pair of neighbouring positive halves, the float midpoint (exact in binary32) goes
    // to the even one, and the floats right beside it go to the nearer one. Covers subnormals,
    // the subnormal/normal boundary and every binade.
    for (std::uint16_t lo = 0; lo < kHalfMaxBits; ++lo) {
        const std::uint16_t hi = std::uint16_t(lo + 1);
        const float mid = (halfToFloat(lo) + halfToFloat(hi)) * 0.5f;
        ASSERT_EQ(double(mid), (double(halfToFloat(lo)) + double(halfToFloat(hi))) / 2.0);
        const std::uint16_t even = (lo & 1u) ? hi : lo;
        EXPECT_EQ(floatToHalf(mid), even) << std::hex << lo;
        EXPECT_EQ(floatToHalf(-mid), std::uint16_t(even | 0x8000u)) << std::hex << lo;
        EXPECT_EQ(floatToHalf(std::nextafter(mid, 0.0f)), lo) << std::hex << lo;
        EXPECT_EQ(floatToHalf(std::nextafter(mid, 1.0e9f)), hi) << std::hex << lo;
    }
    EXPECT_EQ(floatToHalf(1.0f + 0x1p-11f), 0x3C00);     // tie, 1.0 is even
    EXPECT_EQ(floatToHalf(1.0f + 3 * 0x1p-11f), 0x3C02); // tie, rounds up to even
}

TEST(Half, OverflowSaturatesAtTheLargestHalf) {
    EXPECT_EQ(floatToHalf(65519.996f), kHalfMaxBits); // below the rounding point
    EXPECT_EQ(floatToHalf(65520.0f), kHalfMaxBits);   // IEEE would round this to infinity
    EXPECT_EQ(floatToHalf(1.0e10f), kHalfMaxBits);
    EXPECT_EQ(floatToHalf(std::numeric_limits<float>::max()), kHalfMaxBits);
    EXPECT_EQ(floatToHalf(std::numeric_limits<float>::infinity()), kHalfMaxBits);
    EXPECT_EQ(floatToHalf(-std::numeric_limits<float>::infinity()), 0xFBFF);
    EXPECT_EQ(floatToHalf(-1.0e6f), 0xFBFF);
}

TEST(Half, SubnormalsRoundAndTinyValuesGoToSignedZero) {
    EXPECT_EQ(floatToHalf(0x1p-24f), 0x0001);
    EXPECT_EQ(floatToHalf(0x1p-25f), 0x0000);        // tie between 0 and 2^-24: even is 0
    EXPECT_EQ(floatToHalf(0x1.000002p-25f), 0x0001); // just past the tie
    EXPECT_EQ(floatToHalf(1.5f * 0x1p-24f), 0x0002); // tie between 1 and 2: even is 2
    EXPECT_EQ(floatToHalf(0x1p-30f), 0x0000);
    EXPECT_EQ(floatToHalf(-0x1p-30f), 0x8000);
    EXPECT_EQ(floatToHalf(std::numeric_limits<float>::denorm_min()), 0x0000);
    EXPECT_EQ(floatToHalf(0x1.ff8p-15f), 0x03FF); // largest subnormal
    EXPECT_EQ(floatToHalf(0x1.ffcp-15f), 0x0400); // tie: even is 0x400, the smallest normal
    EXPECT_EQ(halfToFloat(0x0200), 0x1p-15f);
    EXPECT_EQ(halfToFloat(0x8001), -0x1p-24f);
}

TEST(Half, InfinityAndNaNDecodeAndNaNStaysNaN) {
    EXPECT_EQ(halfToFloat(0x7C00), std::numeric_limits<float>::infinity());
    EXPECT_EQ(halfToFloat(0xFC00), -std::numeric_limits<float>::infinity());
    EXPECT_TRUE(std::isnan(halfToFloat(0x7E00)));
    EXPECT_TRUE(std::isnan(halfToFloat(0xFC01)));
    EXPECT_TRUE(isNaNBits(floatToHalf(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_TRUE(isNaNBits(floatToHalf(-std::numeric_limits<float>::quiet_NaN())));
    EXPECT_TRUE(isNaNBits(floatToHalf(std::numeric_limits<float>::signaling_NaN())));
}

} // namespace
} // namespace sluice::test
