// Median and range of repeated timings, as the benchmarks report them.
#pragma once

#include <algorithm>
#include <vector>

namespace sluice::bench {

/// The median of a set of timings and its range.
struct Figures {
    double median = 0.0, lo = 0.0, hi = 0.0;
};

/// Figures of `v` (not empty).
inline Figures figures(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return {n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]), v.front(), v.back()};
}

} // namespace sluice::bench
