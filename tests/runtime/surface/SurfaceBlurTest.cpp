// The Gaussian field's blur taps (runtime/src/surface/SurfaceGrid.cpp), on the CPU: as wide as
// poly6 of the support once the deposit's own spread is added, normalised, and refused where
// the cell makes it too narrow or too wide to hold in kSurfaceBlurRadiusMax taps.
#include <gtest/gtest.h>

#include "surface/SurfaceGrid.h"

namespace sluice::rt {
namespace {

SurfaceOptions resolved(float cell, float support) {
    SurfaceOptions o;
    o.particleRadius = 0.01f;
    o.cellSize = cell;
    o.smoothingRadius = support;
    auto r = resolveSurfaceOptions(o);
    EXPECT_TRUE(r) << r.error().message();
    return *r;
}

/// Sum and variance [cells^2] of the taps -radius .. radius.
std::pair<double, double> moments(const SurfaceBlur& b) {
    double sum = b.weights[0];
    double variance = 0.0;
    for (int k = 1; k <= b.radius; ++k) {
        sum += 2.0 * b.weights[std::size_t(k)];
        variance += 2.0 * double(k) * k * b.weights[std::size_t(k)];
    }
    return {sum, variance};
}

TEST(SurfaceBlur, IsAsWideAsPoly6WithTheDepositAndSumsToOne) {
    // poly6's variance per axis is h^2 / 11; the trilinear deposit adds 1/6 cell^2.
    for (float cellsPerSupport : {2.5f, 4.0f, 6.0f, 8.0f}) {
        const float cell = 0.01f;
        const auto blur = gaussianBlur(resolved(cell, cellsPerSupport * cell));
        ASSERT_TRUE(blur) << cellsPerSupport;
        const auto [sum, variance] = moments(*blur);
        EXPECT_NEAR(sum, 1.0, 1e-6) << cellsPerSupport;
        const double poly6 = double(cellsPerSupport) * cellsPerSupport / 11.0;
        // The taps cut at 3.5 sigma lose 0.6 % of the variance.
        EXPECT_NEAR((variance + 1.0 / 6.0) / poly6, 1.0, 0.01) << cellsPerSupport;
        EXPECT_LE(blur->radius, int(shared::kSurfaceBlurRadiusMax));
        for (int k = 1; k <= blur->radius; ++k)
            EXPECT_LT(blur->weights[std::size_t(k)], blur->weights[std::size_t(k - 1)]);
    }
    // The defaults (cell r, support 4 r): taps -4 .. 4.
    EXPECT_EQ(gaussianBlur(resolved(0.01f, 0.04f))->radius, 4);
}

TEST(SurfaceBlur, GivesWayToPoly6WhereTheGaussianDoesNotFitOrIsNotAsked) {
    EXPECT_FALSE(gaussianBlur(resolved(0.01f, 0.02f)));  // half the support: too narrow
    EXPECT_FALSE(gaussianBlur(resolved(0.001f, 0.04f))); // 40 cells: too many taps
    SurfaceOptions poly6 = resolved(0.01f, 0.04f);
    poly6.kernel = SurfaceFieldKernel::Poly6;
    EXPECT_FALSE(gaussianBlur(poly6));
    SurfaceOptions anisotropic = resolved(0.01f, 0.04f);
    anisotropic.anisotropic = true;
    EXPECT_FALSE(gaussianBlur(anisotropic));
}

} // namespace
} // namespace sluice::rt
