// bake::validate against hand-made and CGAL-baked assets whose errors are known exactly.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "TestMeshes.h"
#include "sluice/bake/cgal/CgalBaker.h"
#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/validate/Validate.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::bake {
namespace {

// The box [-1, 1]^3 sampled on a 21^3 grid with spacing 0.125 from -1.25: grid points lie on
// its faces (i = 2 and 18), inside and outside it.
constexpr double kBoxHalf = 1.0;
constexpr double kBoxVoxel = 0.125;
constexpr std::uint32_t kBoxDims = 21;

ImportedMesh boxMesh() {
    return testmesh::imported(testmesh::boxSoup(glm::dvec3(-kBoxHalf), glm::dvec3(kBoxHalf)),
                              "box.obj");
}

/// The analytic box SDF stored in fp32: differs from the CGAL reference only by float rounding.
format::ColliderAsset analyticBoxAsset() {
    format::ColliderAsset asset;
    asset.meta.dims = glm::uvec3(kBoxDims);
    asset.meta.origin = glm::dvec3(-1.25);
    asset.meta.voxelSize = kBoxVoxel;
    asset.meta.bake.backend = "test";
    asset.distances.resize(asset.pointCount());
    for (std::uint32_t k = 0; k < kBoxDims; ++k)
        for (std::uint32_t j = 0; j < kBoxDims; ++j)
            for (std::uint32_t i = 0; i < kBoxDims; ++i)
                asset.distances[asset.index(i, j, k)] = float(testmesh::boxSdf(
                    asset.pointPosition(i, j, k), glm::dvec3(-kBoxHalf), glm::dvec3(kBoxHalf)));
    return asset;
}

/// Points whose exact distance is at least the 1e-4-voxel band: the ones signs are compared at.
std::uint64_t pointsOffTheSurface(const format::ColliderAsset& asset) {
    std::uint64_t count = 0;
    for (std::uint32_t k = 0; k < asset.meta.dims.z; ++k)
        for (std::uint32_t j = 0; j < asset.meta.dims.y; ++j)
            for (std::uint32_t i = 0; i < asset.meta.dims.x; ++i)
                count +=
                    std::abs(testmesh::boxSdf(asset.pointPosition(i, j, k), glm::dvec3(-kBoxHalf),
                                              glm::dvec3(kBoxHalf))) >= 1e-4 * asset.meta.voxelSize
                        ? 1
                        : 0;
    return count;
}

TEST(Validate, CgalBakedSphereMatchesTheReferenceEverywhere) {
    const ImportedMesh mesh =
        testmesh::imported(testmesh::icoSphereSoup(glm::dvec3(0.1, -0.2, 0.3), 1.0, 2));
    BakeSettings settings;
    settings.grid.resolution = 24;
    Result<format::ColliderAsset> asset = bakeCgal(mesh, settings);
    ASSERT_TRUE(asset.ok()) << asset.error().message();

    Result<ValidationReport> report = validate(*asset, mesh, ValidateOptions{});
    ASSERT_TRUE(report.ok()) << report.error().message();
    const format::ValidationFigures& f = report->figures;
    EXPECT_TRUE(f.known);
    EXPECT_FALSE(report->sampled);
    EXPECT_EQ(f.pointsChecked, asset->pointCount());
    EXPECT_EQ(report->referenceSign, format::SignMethod::Parity);
    // fp32 rounding of distances up to ~40 voxels: a few 1e-6 voxels at most.
    EXPECT_LT(f.maxError, 1e-5);
    EXPECT_LE(f.meanError, f.rmsError);
    EXPECT_LE(f.rmsError, f.maxError);
    EXPECT_EQ(f.signMismatches, 0u);
    EXPECT_EQ(report->signMismatchPercent, 0.0);
    EXPECT_GT(report->signComparedPoints, asset->pointCount() * 99 / 100);
    EXPECT_NEAR(f.eikonalMedian, 1.0, 0.05);
    // Central differences of a convex distance overshoot 1 slightly where it curves (~1 %).
    EXPECT_NEAR(f.eikonalP99, 1.0, 0.05);
    EXPECT_LT(f.eikonalOutsideShare, 0.05);
}

TEST(Validate, AnalyticBoxAssetHasOnlyRoundingError) {
    const format::ColliderAsset asset = analyticBoxAsset();
    Result<ValidationReport> report = validate(asset, boxMesh(), ValidateOptions{});
    ASSERT_TRUE(report.ok()) << report.error().message();
    EXPECT_LT(report->figures.maxError, 1e-5);
    EXPECT_EQ(report->figures.signMismatches, 0u);
    EXPECT_EQ(report->signComparedPoints, pointsOffTheSurface(asset));
    // The surface points are excluded: 21^3 minus the points on the faces of the box.
    EXPECT_LT(report->signComparedPoints, asset.pointCount());
}

TEST(Validate, OnePointRaisedByHalfAVoxelGivesThatMaxError) {
    format::ColliderAsset asset = analyticBoxAsset();
    const std::uint64_t raised = asset.index(2, 10, 10); // on the -x face: phi = 0 exactly
    ASSERT_EQ(asset.distances[raised], 0.0f);
    asset.distances[raised] += float(0.5 * kBoxVoxel);

    Result<ValidationReport> report = validate(asset, boxMesh(), ValidateOptions{});
    ASSERT_TRUE(report.ok()) << report.error().message();
    EXPECT_NEAR(report->figures.maxError, 0.5, 1e-6);
    // Every other point is within rounding, so the mean is the one error shared by all points.
    EXPECT_NEAR(report->figures.meanError, 0.5 / double(asset.pointCount()), 1e-6);
    EXPECT_NEAR(report->figures.rmsError, std::sqrt(0.25 / double(asset.pointCount())), 1e-6);
    EXPECT_EQ(report->figures.signMismatches, 0u); // the raised point lies on the surface
}

TEST(Validate, SignsFlippedFarFromTheSurfaceAreCountedExactly) {
    format::ColliderAsset asset = analyticBoxAsset();
    // Seven points at least 2 voxels from every face: three inside, four outside.
    const glm::uvec3 flipped[] = {{10, 10, 10}, {6, 10, 12}, {14, 7, 10}, {0, 0, 0},
                                  {20, 10, 10}, {10, 0, 20}, {0, 20, 5}};
    double largestJump = 0.0;
    for (const glm::uvec3& p : flipped) {
        float& phi = asset.distances[asset.index(p.x, p.y, p.z)];
        ASSERT_GE(std::abs(phi), 2.0 * kBoxVoxel);
        largestJump = std::max(largestJump, 2.0 * std::abs(double(phi)) / kBoxVoxel);
        phi = -phi;
    }

    Result<ValidationReport> report = validate(asset, boxMesh(), ValidateOptions{});
    ASSERT_TRUE(report.ok()) << report.error().message();
    EXPECT_EQ(report->figures.signMismatches, 7u);
    const std::uint64_t compared = pointsOffTheSurface(asset);
    EXPECT_EQ(report->signComparedPoints, compared);
    EXPECT_NEAR(report->signMismatchPercent, 700.0 / double(compared), 1e-9);
    EXPECT_NEAR(report->figures.maxError, largestJump, 1e-5);
}

TEST(Validate, TinyValuesOfTheWrongSignAtTheSurfaceAreNotMismatches) {
    format::ColliderAsset asset = analyticBoxAsset();
    // On the faces the reference is exactly 0 (outside by the sign rule); a value of -1e-6
    // voxels is inside by its sign bit but within the 1e-4-voxel band, so it is not counted.
    std::uint64_t changed = 0;
    for (float& phi : asset.distances)
        if (phi == 0.0f) {
            phi = float(-1e-6 * kBoxVoxel);
            ++changed;
        }
    ASSERT_GT(changed, 0u);
    Result<ValidationReport> report = validate(asset, boxMesh(), ValidateOptions{});
    ASSERT_TRUE(report.ok()) << report.error().message();
    EXPECT_EQ(report->figures.signMismatches, 0u);

    // With no band at all they are mismatches, one per changed point.
    ValidateOptions noBand;
    noBand.surfaceBand = 0.0;
    Result<ValidationReport> strict = validate(asset, boxMesh(), noBand);
    ASSERT_TRUE(strict.ok()) << strict.error().message();
    EXPECT_EQ(strict->figures.signMismatches, changed);
}

TEST(Validate, SampledValidationIsDeterministicForASeed) {
    format::ColliderAsset asset = analyticBoxAsset();
    asset.distances[asset.index(10, 10, 10)] += float(0.25 * kBoxVoxel); // one known error
    ValidateOptions options;
    options.maxFullPoints = 1000;
    options.samplePoints = 2000;
    options.seed = 42;

    Result<ValidationReport> first = validate(asset, boxMesh(), options);
    Result<ValidationReport> second = validate(asset, boxMesh(), options);
    ASSERT_TRUE(first.ok() && second.ok());
    EXPECT_TRUE(first->sampled);
    EXPECT_EQ(first->figures.pointsChecked, 2000u);
    EXPECT_EQ(first->figures.pointsChecked, second->figures.pointsChecked);
    EXPECT_EQ(first->figures.maxError, second->figures.maxError);
    EXPECT_EQ(first->figures.meanError, second->figures.meanError);
    EXPECT_EQ(first->figures.rmsError, second->figures.rmsError);
    EXPECT_EQ(first->signComparedPoints, second->signComparedPoints);
    EXPECT_EQ(first->figures.signMismatches, 0u);
    // Every sampled error is rounding or the one raised point: the max is one or the other.
    EXPECT_TRUE(first->figures.maxError < 1e-5 || std::abs(first->figures.maxError - 0.25) < 1e-6)
        << first->figures.maxError;

    // Another seed draws other points (the 2000 of 9261 differ, so the sums do too).
    options.seed = 43;
    Result<ValidationReport> other = validate(asset, boxMesh(), options);
    ASSERT_TRUE(other.ok());
    EXPECT_TRUE(other->sampled);
    EXPECT_EQ(other->figures.pointsChecked, 2000u);
    EXPECT_NE(other->figures.meanError, first->figures.meanError);
    // Eikonal statistics use every interior point, sampled or not.
    EXPECT_EQ(other->figures.eikonalMedian, first->figures.eikonalMedian);
}

TEST(Validate, SampleTakesItsShareNearTheSurface) {
    // Near-surface errors only: every point within 2 voxels of the surface is raised by 0.1
    // voxel. With the whole sample near the surface every checked point shows it; with none
    // there, no point does.
    format::ColliderAsset asset = analyticBoxAsset();
    for (float& phi : asset.distances)
        if (std::abs(phi) < 2.0 * kBoxVoxel)
            phi += float(0.1 * kBoxVoxel);
    ValidateOptions options;
    options.maxFullPoints = 1000;
    options.samplePoints = 500;
    options.nearSurfaceShare = 1.0;
    Result<ValidationReport> nearOnly = validate(asset, boxMesh(), options);
    ASSERT_TRUE(nearOnly.ok());
    EXPECT_NEAR(nearOnly->figures.meanError, 0.1, 1e-5);
    options.nearSurfaceShare = 0.0;
    Result<ValidationReport> farOnly = validate(asset, boxMesh(), options);
    ASSERT_TRUE(farOnly.ok());
    EXPECT_LT(farOnly->figures.maxError, 1e-5);
}

TEST(Validate, RejectsAnAssetWhoseSamplesDoNotMatchItsGrid) {
    format::ColliderAsset asset = analyticBoxAsset();
    asset.distances.pop_back();
    Result<ValidationReport> report = validate(asset, boxMesh(), ValidateOptions{});
    ASSERT_FALSE(report.ok());
    EXPECT_EQ(report.error().code, ErrorCode::InvalidArgument);
}

TEST(Validate, ParityOnAnOpenMeshIsRefused) {
    const ImportedMesh open = testmesh::imported(
        testmesh::boxSoup(glm::dvec3(-kBoxHalf), glm::dvec3(kBoxHalf), /*withoutTop=*/true));
    ValidateOptions options;
    options.sign = SignMode::Parity;
    Result<ValidationReport> report = validate(analyticBoxAsset(), open, options);
    ASSERT_FALSE(report.ok());
    EXPECT_EQ(report.error().code, ErrorCode::InvalidArgument);
}

} // namespace
} // namespace sluice::bake
