// Shared by the fuzz targets: the largest single allocation during a call, and loud failures.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "sluice/format/support/Result.h"
#include "sluice/format/support/Sanitizers.h"

#if defined(SLUICE_ADDRESS_SANITIZER)
// From <sanitizer/allocator_interface.h>, which clang ships and GCC does not (its libasan has
// the function all the same).
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*mallocHook)(const volatile void*,
                                                                            std::size_t),
                                                         void (*freeHook)(const volatile void*));
#endif

namespace sluice::fuzz {

/// A broken invariant: prints it and aborts, which libFuzzer records as a crash (and the
/// corpus replay as a failed test).
[[noreturn]] inline void violated(const char* what, const char* detail = "") {
    std::fprintf(stderr, "fuzz invariant broken: %s %s\n", what, detail);
    std::fflush(stderr);
    std::abort();
}

#define SLUICE_FUZZ_CHECK(cond, detail)                                                            \
    do {                                                                                           \
        if (!(cond))                                                                               \
            ::sluice::fuzz::violated(#cond, (detail));                                             \
    } while (0)

namespace detail {
inline std::atomic<std::size_t> g_largest{0};
inline std::atomic<bool> g_armed{false};
#if defined(SLUICE_ADDRESS_SANITIZER)
inline void onMalloc(const volatile void*, std::size_t size) {
    if (!g_armed.load(std::memory_order_relaxed))
        return;
    std::size_t seen = g_largest.load(std::memory_order_relaxed);
    while (size > seen && !g_largest.compare_exchange_weak(seen, size, std::memory_order_relaxed)) {
    }
}
inline void onFree(const volatile void*) {}
#endif
} // namespace detail

/// Records the largest single malloc / operator new request between construction and check()
/// through the sanitizer allocator hooks. Without ASan it records nothing and checks nothing.
class AllocationWatch {
public:
    AllocationWatch() {
#if defined(SLUICE_ADDRESS_SANITIZER)
        static const bool installed =
            __sanitizer_install_malloc_and_free_hooks(&detail::onMalloc, &detail::onFree) != 0;
        (void)installed;
#endif
        detail::g_largest.store(0);
        detail::g_armed.store(true);
    }
    ~AllocationWatch() {
        detail::g_armed.store(false);
    }
    AllocationWatch(const AllocationWatch&) = delete;
    AllocationWatch& operator=(const AllocationWatch&) = delete;

    /// [bytes] the largest request so far.
    std::size_t largest() const {
        return detail::g_largest.load();
    }

    /// Aborts if a single request exceeded `limit` [bytes]: the reader allocated more than its
    /// input justifies.
    void check(std::size_t limit, const char* reader) const {
        const std::size_t seen = largest();
        if (seen > limit) {
            char text[160];
            std::snprintf(text, sizeof text, "%s allocated %zu bytes at once, limit %zu", reader,
                          seen, limit);
            violated("allocation bounded by the input", text);
        }
    }
};

/// What a reader returned for the input called `name`: a value goes into `accepted` (true); an
/// error (false) must name the input first, as every reader's message does.
template <typename T> bool takeResult(Result<T>& r, T& accepted, std::string_view name) {
    if (r) {
        accepted = std::move(*r);
        return true;
    }
    SLUICE_FUZZ_CHECK(r.error().detail.rfind(name, 0) == 0, "messages start with the file name");
    return false;
}

/// One fuzz input, checked twice: the bytes as they are, then a copy that `repair` fixes in the
/// one field that stops the reader at its first check (a checksum, a size), so that the checks
/// behind it see fuzzed data too. `repair` returns false where the input is too short for it.
template <typename Check, typename Repair>
int checkAsIsAndRepaired(const std::uint8_t* data, std::size_t size, Check check, Repair repair) {
    const auto bytes = std::as_bytes(std::span(data, size));
    check(bytes);
    std::vector<std::byte> repaired(bytes.begin(), bytes.end());
    if (repair(repaired))
        check(std::span<const std::byte>(repaired));
    return 0;
}

} // namespace sluice::fuzz
