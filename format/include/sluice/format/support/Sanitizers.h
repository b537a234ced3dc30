// Whether this translation unit is built with AddressSanitizer (GCC's __SANITIZE_ADDRESS__,
// clang's __has_feature), for the few places that must act differently under it.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define SLUICE_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SLUICE_ADDRESS_SANITIZER 1
#endif
#endif

namespace sluice {

#ifdef SLUICE_ADDRESS_SANITIZER
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif

} // namespace sluice
