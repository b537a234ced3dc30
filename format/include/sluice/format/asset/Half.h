// IEEE binary16 (fp16) <-> binary32 conversion for fp16 distance storage.
#pragma once

#include <cstdint>

namespace sluice::format {

/// Largest finite fp16 value, 65504.
inline constexpr float kHalfMax = 65504.0f;
/// Bits of +kHalfMax.
inline constexpr std::uint16_t kHalfMaxBits = 0x7BFF;

/// Converts to fp16 bits with round-to-nearest-even, subnormals included (no flush to zero).
/// Saturating: finite values that would round past kHalfMax, and infinities, become
/// +-kHalfMax (a stored distance has no use for infinity). NaN becomes a quiet NaN with the same
/// sign. Integer arithmetic only, so the result does not depend on the FPU rounding mode.
std::uint16_t floatToHalf(float value);

/// Converts fp16 bits to float. Exact: every fp16 value (subnormals, +-0, +-inf, NaN) is
/// representable in binary32.
float halfToFloat(std::uint16_t bits);

} // namespace sluice::format
