// Private helpers: little-endian loads and stores on byte buffers, and overflow-checked sums.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <type_traits>

namespace sluice::format::detail {

/// Stores `value` as `N` little-endian bytes at `out` (N = sizeof(T)).
template <class T> inline void storeLE(std::byte* out, T value) {
    static_assert(std::is_unsigned_v<T>);
    for (std::size_t i = 0; i < sizeof(T); ++i)
        out[i] = std::byte((value >> (8 * i)) & 0xFFu);
}

/// Loads a little-endian unsigned integer of sizeof(T) bytes from `in`.
template <class T> inline T loadLE(const std::byte* in) {
    static_assert(std::is_unsigned_v<T>);
    T value = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i)
        value = T(value | (T(std::to_integer<std::uint8_t>(in[i])) << (8 * i)));
    return value;
}

/// a + b, or nothing if it overflows 64 bits.
inline std::optional<std::uint64_t> checkedAdd(std::uint64_t a, std::uint64_t b) {
    std::uint64_t sum = 0;
    if (__builtin_add_overflow(a, b, &sum))
        return std::nullopt;
    return sum;
}

/// a * b, or nothing if it overflows 64 bits.
inline std::optional<std::uint64_t> checkedMul(std::uint64_t a, std::uint64_t b) {
    std::uint64_t product = 0;
    if (__builtin_mul_overflow(a, b, &product))
        return std::nullopt;
    return product;
}

/// Rounds `value` up to a multiple of `alignment` (a power of two); nothing on overflow.
inline std::optional<std::uint64_t> alignUp(std::uint64_t value, std::uint64_t alignment) {
    auto bumped = checkedAdd(value, alignment - 1);
    if (!bumped)
        return std::nullopt;
    return *bumped & ~(alignment - 1);
}

} // namespace sluice::format::detail
