// Private: what both validations (dense and sparse) sum over the points they compare.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace sluice::bake::detail {

/// Error sums over points compared with the reference, and the sign comparisons outside the
/// surface band.
struct PointComparison {
    double sum = 0.0;             ///< of |phi - exact| [voxels]
    double sumSquare = 0.0;       ///< of its squares [voxels^2]
    std::uint64_t compared = 0;   ///< points outside the surface band, their signs compared
    std::uint64_t mismatches = 0; ///< of those, the points whose signs differ

    /// Adds the error of `phi` against `exact` [world units] in voxels of `h`, and raises
    /// `maxError` to it (a NaN error counts as infinite).
    void addError(float phi, double exact, double h, double& maxError) {
        const double error = std::abs(double(phi) - exact) / h;
        sum += error;
        sumSquare += error * error;
        maxError = std::max(maxError, std::isnan(error) ? INFINITY : error);
    }

    /// Compares the signs of `phi` and `exact` where |exact| >= `surface` [world units].
    void addSign(float phi, double exact, double surface) {
        if (std::abs(exact) < surface)
            return;
        ++compared;
        // signbit, so a tiny negative distance rounded to -0 by fp16 still counts inside.
        if (std::signbit(phi) != (exact < 0.0))
            ++mismatches;
    }
};

} // namespace sluice::bake::detail
