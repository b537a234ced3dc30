// Particle counts of fluid blocks and emitter discs by the lattice rules of docs/pbf.md.
#include "sluice/format/scene/SceneIO.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace sluice::format {

namespace {

// Slack on the lattice-membership tests in units of the spacing, exactly as rt::fillBlocks and
// rt::emitterDisc use it (docs/pbf.md), so a rim point float rounding would drop is kept.
constexpr double kLatticeSlack = 1e-4;

// Returned for a shape that surely holds more than the limit, without enumerating it.
constexpr std::uint64_t kSaturated = std::uint64_t(kMaxSceneParticles) + 1;

// Largest n >= 0 with inside(n), for inside() true up to some n and false after; -1 if
// inside(0) is false. Starts from a guess, so the cost is the guess's error, not n.
template <class Inside> std::int64_t largestInside(std::int64_t guess, Inside inside) {
    if (!inside(0))
        return -1;
    std::int64_t n = std::max<std::int64_t>(guess, 0);
    while (n > 0 && !inside(n))
        --n;
    while (inside(n + 1))
        ++n;
    return n;
}

} // namespace

std::uint64_t blockParticleCount(const FluidBlock& block, float spacing) {
    if (block.shape == FluidBlock::Shape::Box) {
        double product = 1.0;
        for (int a = 0; a < 3; ++a) {
            const double n =
                std::floor((double(block.max[a]) - block.min[a]) / spacing + kLatticeSlack);
            if (!(n > 0.0))
                return 0;
            product *= double(n);
        }
        return product > double(kMaxSceneParticles) ? kSaturated : std::uint64_t(product);
    }
    // Sphere: lattice points centre + s (i, j, k) with |s (i, j, k)| <= radius - s / 2 + slack.
    const double s = spacing;
    const double reach = double(block.radius) - 0.5 * s + kLatticeSlack * s;
    if (!(reach >= 0.0f))
        return 0;
    const double rho = double(reach) / double(spacing); // [lattice steps]
    // Past 300 steps the inscribed cube alone, (2 floor(300 / sqrt 3) + 1)^3 = 347^3 points,
    // is over the limit.
    if (!(rho <= 300.0))
        return kSaturated;
    const auto k = std::int64_t(std::ceil(rho)) + 1;
    std::uint64_t count = 0;
    for (std::int64_t i = -k; i <= k; ++i) {
        for (std::int64_t j = -k; j <= k; ++j) {
            const double rest = rho * rho - double(i * i + j * j);
            const auto guess = std::int64_t(std::sqrt(std::max(rest, 0.0)));
            const std::int64_t last = largestInside(guess, [&](std::int64_t n) {
                return glm::length(s * glm::dvec3(double(i), double(j), double(n))) <= reach;
            });
            if (last >= 0)
                count += std::uint64_t(2 * last + 1);
        }
    }
    return count;
}

std::uint64_t emitterDiscCount(float radius, float spacing) {
    const double rho = double(radius) / double(spacing); // [lattice steps]
    if (!(rho >= 0.0))
        return 0;
    // Past 3000 steps the inscribed square alone, (2 floor(3000 / sqrt 2) + 1)^2 = 4243^2
    // points, is over the limit.
    if (!(rho <= 3000.0))
        return kSaturated;
    const auto k = std::int64_t(std::ceil(rho)) + 1;
    const double s = spacing;
    const double reach = double(radius) + kLatticeSlack * s;
    std::uint64_t count = 0;
    for (std::int64_t b = -k; b <= k; ++b) {
        const auto guess = std::int64_t(std::sqrt(std::max(rho * rho - double(b * b), 0.0)));
        const std::int64_t last = largestInside(
            guess, [&](std::int64_t a) { return s * std::sqrt(double(a * a + b * b)) <= reach; });
        if (last >= 0)
            count += std::uint64_t(2 * last + 1);
    }
    return count;
}

} // namespace sluice::format
