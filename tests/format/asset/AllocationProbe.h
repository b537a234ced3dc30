// Records the largest single operator-new request, to prove a reader did not allocate from a
// hostile size (the test binary replaces the global operator new; see AllocationProbe.cpp).
#pragma once

#include <cstddef>

namespace sluice::test {

/// Forgets the largest request seen so far.
void resetLargestAllocation();

/// [bytes] the largest single operator new / new[] request since the last reset.
std::size_t largestAllocation();

} // namespace sluice::test
