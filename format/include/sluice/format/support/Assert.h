// Contract checks for broken invariants inside the code (never for untrusted input).
#pragma once

namespace sluice {

/// Called by SLUICE_ASSERT on failure. The default prints the location and aborts; the test main
/// installs a handler that turns the failure into a failed test.
using AssertHandler = void (*)(const char* expr, const char* msg, const char* file, int line);

/// Replaces the assert handler and returns the previous one.
AssertHandler setAssertHandler(AssertHandler handler);

[[noreturn]] void assertFailed(const char* expr, const char* msg, const char* file, int line);

} // namespace sluice

/// Always on, in every build type: checks a contract, calls the assert handler if it is broken.
#define SLUICE_ASSERT(cond, msg)                                                                   \
    do {                                                                                           \
        if (!(cond))                                                                               \
            ::sluice::assertFailed(#cond, (msg), __FILE__, __LINE__);                              \
    } while (0)
