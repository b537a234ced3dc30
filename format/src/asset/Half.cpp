// fp16 conversion with round-to-nearest-even, done on the bit patterns.
#include "sluice/format/asset/Half.h"

#include <bit>

namespace sluice::format {

namespace {
// Rounds m >> shift to the nearest integer, ties to even (shift in [1, 31]).
std::uint32_t shiftRoundEven(std::uint32_t m, std::uint32_t shift) {
    const std::uint32_t q = m >> shift;
    const std::uint32_t rem = m & ((1u << shift) - 1u);
    const std::uint32_t half = 1u << (shift - 1u);
    return (rem > half || (rem == half && (q & 1u))) ? q + 1u : q;
}
} // namespace

std::uint16_t floatToHalf(float value) {
    const std::uint32_t x = std::bit_cast<std::uint32_t>(value);
    const auto sign = std::uint16_t((x >> 16) & 0x8000u);
    const std::uint32_t absBits = x & 0x7FFFFFFFu;

    if (absBits > 0x7F800000u) // NaN: keep it a NaN, quiet
        return std::uint16_t(sign | 0x7E00u);
    // 65520 = kHalfMax + half an ulp: at and past it IEEE rounding gives infinity; saturate.
    if (absBits >= 0x477FF000u)
        return std::uint16_t(sign | kHalfMaxBits);

    const std::uint32_t exponent = absBits >> 23; // biased by 127
    const std::uint32_t mantissa = absBits & 0x7FFFFFu;
    if (exponent >= 113) {
        // Normal fp16: rebias the exponent (127 -> 15) and round away the 13 extra mantissa
        // bits. A carry out of the mantissa correctly bumps the exponent.
        const std::uint32_t bits = ((exponent - 112u) << 10) | (mantissa >> 13);
        const std::uint32_t rem = mantissa & 0x1FFFu;
        const bool up = rem > 0x1000u || (rem == 0x1000u && (bits & 1u));
        return std::uint16_t(sign | (bits + (up ? 1u : 0u)));
    }
    if (exponent < 102) // below 2^-25, half the smallest subnormal: rounds to zero
        return sign;
    // Subnormal fp16, value = q * 2^-24 with q = (1.mantissa * 2^23) >> (126 - exponent).
    // Rounding up to q = 0x400 yields the smallest normal, whose bits are exactly 0x400.
    const std::uint32_t full = mantissa | 0x800000u;
    return std::uint16_t(sign | shiftRoundEven(full, 126u - exponent));
}

float halfToFloat(std::uint16_t bits) {
    const std::uint32_t sign = std::uint32_t(bits & 0x8000u) << 16;
    const std::uint32_t exponent = (bits >> 10) & 0x1Fu;
    std::uint32_t mantissa = bits & 0x3FFu;

    std::uint32_t out = 0;
    if (exponent == 0x1F) {
        out = sign | 0x7F800000u | (mantissa << 13); // inf or NaN (payload kept)
    } else if (exponent != 0) {
        out = sign | ((exponent + 112u) << 23) | (mantissa << 13);
    } else if (mantissa == 0) {
        out = sign; // +-0
    } else {
        // Subnormal: normalize. Value = mantissa * 2^-24.
        std::uint32_t e = 113; // biased exponent of 2^-14
        while ((mantissa & 0x400u) == 0) {
            mantissa <<= 1;
            --e;
        }
        out = sign | (e << 23) | ((mantissa & 0x3FFu) << 13);
    }
    return std::bit_cast<float>(out);
}

} // namespace sluice::format
