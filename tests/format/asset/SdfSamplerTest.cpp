// SdfSampler: exact on linear fields, accurate on a sphere, and the documented outside rule.
#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "AnalyticAsset.h"
#include "sluice/format/asset/SdfSampler.h"

namespace sluice::test {
namespace {

using namespace sluice::format;

ColliderAsset gridOf(glm::uvec3 dims, glm::dvec3 origin, double h,
                     double (*phi)(const glm::dvec3&)) {
    return testasset::assetFromSdf(dims, origin, h, phi);
}

const glm::dvec3 kSlope{0.3, -0.5, 0.8};
double linear(const glm::dvec3& p) {
    return glm::dot(kSlope, p) + 0.25;
}

const glm::dvec3 kCentre{0.1, -0.2, 0.3};
double sphere(const glm::dvec3& p) {
    return glm::length(p - kCentre) - 0.6;
}

glm::dvec3 randomIn(std::mt19937& rng, glm::dvec3 lo, glm::dvec3 hi) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return lo + (hi - lo) * glm::dvec3(u(rng), u(rng), u(rng));
}

TEST(SdfSampler, IsExactOnALinearFieldWithItsSlopeAsGradient) {
    const ColliderAsset a = gridOf({5, 6, 7}, {-1.2, 0.3, 2.0}, 0.25, &linear);
    const SdfSampler s(a);
    std::mt19937 rng(7);
    for (int n = 0; n < 2000; ++n) {
        const glm::dvec3 p = randomIn(rng, a.meta.origin, s.boxMax());
        ASSERT_TRUE(s.contains(p));
        EXPECT_NEAR(s.value(p), linear(p), 2e-6) << n; // float samples: ~1 ulp of |phi| < 4
        const glm::dvec3 g = s.gradient(p);
        EXPECT_NEAR(g.x, kSlope.x, 1e-5);
        EXPECT_NEAR(g.y, kSlope.y, 1e-5);
        EXPECT_NEAR(g.z, kSlope.z, 1e-5);
    }
}

TEST(SdfSampler, ReturnsTheSampleAtGridPointsAndCorners) {
    const ColliderAsset a = gridOf({4, 3, 5}, {0.5, -1.0, 0.0}, 0.2, &sphere);
    const SdfSampler s(a);
    for (std::uint32_t k = 0; k < 5; ++k)
        for (std::uint32_t j = 0; j < 3; ++j)
            for (std::uint32_t i = 0; i < 4; ++i)
                EXPECT_FLOAT_EQ(s.value(a.pointPosition(i, j, k)), a.distances[a.index(i, j, k)]);
    EXPECT_TRUE(s.contains(a.meta.origin));
    EXPECT_TRUE(s.contains(s.boxMax()));
    EXPECT_FALSE(s.contains(s.boxMax() + glm::dvec3(1e-9, 0, 0)));
    EXPECT_FALSE(s.contains(a.meta.origin - glm::dvec3(0, 0, 1e-9)));
}

TEST(SdfSampler, ApproximatesASphereWithinTheTrilinearErrorBound) {
    // Trilinear error <= (3/8) h^2 max|d2phi| and |d2phi| <= 1/r at distance r from the centre;
    // sampled at r >= 0.3 with h = 0.05: bound 0.0031. Gradient error is first order in h.
    const double h = 0.05;
    const ColliderAsset a = gridOf({41, 41, 41}, kCentre - glm::dvec3(1.0), h, &sphere);
    const SdfSampler s(a);
    std::mt19937 rng(11);
    double worstValue = 0.0, worstAngle = 0.0;
    for (int n = 0; n < 5000; ++n) {
        const glm::dvec3 p = randomIn(rng, a.meta.origin, s.boxMax());
        const double r = glm::length(p - kCentre);
        if (r < 0.3)
            continue;
        worstValue = std::max(worstValue, std::abs(double(s.value(p)) - sphere(p)));
        const glm::dvec3 g = glm::normalize(s.gradient(p));
        worstAngle = std::max(worstAngle, std::acos(std::min(1.0, glm::dot(g, (p - kCentre) / r))));
    }
    EXPECT_LT(worstValue, 3.0 / 8.0 * h * h / 0.3);
    EXPECT_GT(worstValue, 0.0); // the test would notice if the sampler returned the exact field
    EXPECT_LT(worstAngle, 0.1); // [rad]
}

TEST(SdfSampler, OutsideAddsTheDistanceToTheBoxAndItsGradientPointsAway) {
    const ColliderAsset a = gridOf({5, 6, 7}, {-1.2, 0.3, 2.0}, 0.25, &linear);
    const SdfSampler s(a);
    const glm::dvec3 lo = a.meta.origin, hi = s.boxMax();
    const glm::dvec3 mid = (lo + hi) * 0.5;

    // Beyond the +x face only: value grows by the distance, gradient.x is +1 (away), y and z keep
    // the slope of the field on the face.
    const glm::dvec3 px{hi.x + 0.7, mid.y, mid.z};
    const glm::dvec3 cx{hi.x, mid.y, mid.z};
    EXPECT_FALSE(s.contains(px));
    EXPECT_NEAR(s.value(px), s.value(cx) + 0.7, 1e-5);
    const glm::dvec3 gx = s.gradient(px);
    EXPECT_NEAR(gx.x, 1.0, 1e-9);
    EXPECT_NEAR(gx.y, kSlope.y, 1e-5);
    EXPECT_NEAR(gx.z, kSlope.z, 1e-5);

    // Beyond the -x face: the away direction is -x, whatever the field's slope says.
    const glm::dvec3 nx{lo.x - 0.2, mid.y, mid.z};
    EXPECT_NEAR(s.gradient(nx).x, -1.0, 1e-9);

    // Off a corner: value = phi(corner) + |p - corner|; gradient is the unit vector from the
    // corner, since every axis is clamped.
    const glm::dvec3 offset{-0.3, 0.4, 1.2};
    const glm::dvec3 corner{lo.x, hi.y, hi.z};
    const glm::dvec3 pc = corner + offset;
    EXPECT_NEAR(s.value(pc), linear(corner) + glm::length(offset), 1e-5);
    const glm::dvec3 gc = s.gradient(pc);
    EXPECT_NEAR(glm::length(gc - glm::normalize(offset)), 0.0, 1e-9);

    // Everywhere outside: the gradient has a positive component away from the box.
    std::mt19937 rng(3);
    for (int n = 0; n < 1000; ++n) {
        const glm::dvec3 p = randomIn(rng, lo - glm::dvec3(5.0), hi + glm::dvec3(5.0));
        if (s.contains(p))
            continue;
        const glm::dvec3 away = p - glm::clamp(p, lo, hi);
        EXPECT_NEAR(glm::dot(s.gradient(p), away), glm::length(away), 1e-9);
        EXPECT_GE(s.value(p), s.value(glm::clamp(p, lo, hi)));
    }
}

TEST(SdfSampler, NonFiniteQueriesGiveNaNInsteadOfUndefinedBehaviour) {
    const ColliderAsset a = gridOf({2, 2, 2}, {0, 0, 0}, 1.0, &linear);
    const SdfSampler s(a);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(std::isnan(s.value({nan, 0, 0})));
    EXPECT_TRUE(std::isnan(s.gradient({0, std::numeric_limits<double>::infinity(), 0}).y));
    EXPECT_FALSE(s.contains({nan, 0.5, 0.5}));
}

TEST(SdfSampler, RefusesAnAssetWhoseSamplesDoNotMatchItsDims) {
    ColliderAsset a = gridOf({3, 3, 3}, {0, 0, 0}, 1.0, &linear);
    a.distances.pop_back();
    EXPECT_ANY_THROW(SdfSampler{a}); // the test main turns SLUICE_ASSERT into an exception
}

} // namespace
} // namespace sluice::test
