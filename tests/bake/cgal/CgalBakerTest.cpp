// The CGAL reference and the CGAL bake against analytic signed distance fields (the grid they
// sample is tested in GridTest.cpp).
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "TestMeshes.h"
#include "sluice/bake/Grid.h"
#include "sluice/bake/cgal/CgalBaker.h"
#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/jobs/Progress.h"

namespace {

using namespace sluice;
using namespace sluice::bake;

/// Every grid point of the bake grid for `soup`, x fastest (the asset's order).
std::vector<glm::dvec3> gridPoints(const GridSpec& grid) {
    std::vector<glm::dvec3> points;
    points.reserve(grid.pointCount());
    for (std::uint32_t k = 0; k < grid.dims.z; ++k)
        for (std::uint32_t j = 0; j < grid.dims.y; ++j)
            for (std::uint32_t i = 0; i < grid.dims.x; ++i)
                points.push_back(grid.origin + glm::dvec3(i, j, k) * grid.voxelSize);
    return points;
}

GridSpec gridOf(const TriangleSoup& soup, std::uint32_t resolution, double padding = 3.0) {
    Result<GridSpec> grid = gridFor(soup.bounds(), {.resolution = resolution, .padding = padding});
    SLUICE_ASSERT(grid.ok(), "test grid");
    return *grid;
}

CgalReference referenceOf(const TriangleSoup& soup, SignMode mode) {
    Result<CgalReference> reference = CgalReference::build(soup, diagnose(soup), mode);
    SLUICE_ASSERT(reference.ok(), "test reference");
    return std::move(reference).value();
}

// --- Sign modes and contracts ----------------------------------------------------------------

TEST(SignMode, ParsesItsThreeNamesAndNothingElse) {
    for (SignMode mode : {SignMode::Auto, SignMode::Parity, SignMode::Winding}) {
        Result<SignMode> parsed = parseSignMode(signModeName(mode));
        ASSERT_TRUE(parsed.ok());
        EXPECT_EQ(*parsed, mode);
    }
    EXPECT_EQ(parseSignMode("Parity").error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(parseSignMode("").error().code, ErrorCode::InvalidArgument);
}

TEST(CgalReference, RefusesParityOnAnOpenMesh) {
    const TriangleSoup open = testmesh::boxSoup({0, 0, 0}, {1, 1, 1}, true);
    Result<CgalReference> reference = CgalReference::build(open, diagnose(open), SignMode::Parity);
    ASSERT_FALSE(reference.ok());
    EXPECT_EQ(reference.error().code, ErrorCode::InvalidArgument);
}

TEST(CgalReference, RefusesASoupOfOnlyDegenerateTrianglesAsEmptyMesh) {
    TriangleSoup soup;
    soup.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    soup.triangles = {{0, 1, 2}, {0, 0, 1}};
    Result<CgalReference> reference = CgalReference::build(soup, diagnose(soup), SignMode::Auto);
    ASSERT_FALSE(reference.ok());
    EXPECT_EQ(reference.error().code, ErrorCode::EmptyMesh);
}

TEST(CgalReference, AutoPicksParityForClosedCleanMeshesAndWindingOtherwise) {
    const TriangleSoup closed = testmesh::boxSoup({0, 0, 0}, {1, 1, 1});
    EXPECT_EQ(referenceOf(closed, SignMode::Auto).signMethod(), format::SignMethod::Parity);
    EXPECT_EQ(referenceOf(closed, SignMode::Winding).signMethod(), format::SignMethod::Winding);
    const TriangleSoup open = testmesh::boxSoup({0, 0, 0}, {1, 1, 1}, true);
    EXPECT_EQ(referenceOf(open, SignMode::Auto).signMethod(), format::SignMethod::Winding);
    EXPECT_TRUE(referenceOf(closed, SignMode::Auto).signFallbackReason().empty());
}

TEST(CgalReference, OrientsAnInconsistentlyWoundClosedMeshForParity) {
    const glm::dvec3 lo{0, 0, 0}, hi{1, 1, 1};
    TriangleSoup box = testmesh::boxSoup(lo, hi);
    for (std::size_t t = 0; t < box.triangles.size(); t += 3)
        std::swap(box.triangles[t].y, box.triangles[t].z);
    const CgalReference reference = referenceOf(box, SignMode::Parity);
    EXPECT_EQ(reference.signMethod(), format::SignMethod::Parity);
    EXPECT_TRUE(reference.signFallbackReason().empty());
    for (const glm::dvec3& p : {glm::dvec3(0.5, 0.5, 0.4), glm::dvec3(0.1, 0.9, 0.2),
                                glm::dvec3(1.5, 0.5, 0.5), glm::dvec3(-1, -1, -1)})
        EXPECT_NEAR(reference.signedDistance(p), testmesh::boxSdf(p, lo, hi), 1e-12);
}

TEST(CgalReference, FallsBackFromParityToWindingOnAClosedSoupThatIsNoOrientableMesh) {
    // The 6-vertex real projective plane: every edge in exactly two triangles, so "closed",
    // but not orientable, so no Surface_mesh can hold it.
    TriangleSoup plane;
    plane.positions = {{0, 0, 1},      {1, 0, 0.1},       {0.3, 0.95, -0.2},
                       {-0.8, 0.6, 0}, {-0.7, -0.7, 0.3}, {0.3, -0.9, -0.4}};
    plane.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 1},
                       {1, 2, 4}, {2, 3, 5}, {3, 4, 1}, {4, 5, 2}, {5, 1, 3}};
    const format::MeshDiagnostics diagnostics = diagnose(plane);
    ASSERT_TRUE(diagnostics.closed);
    Result<CgalReference> reference = CgalReference::build(plane, diagnostics, SignMode::Parity);
    ASSERT_TRUE(reference.ok()) << reference.error().message();
    EXPECT_EQ(reference->signMethod(), format::SignMethod::Winding);
    EXPECT_FALSE(reference->signFallbackReason().empty());
    EXPECT_TRUE(std::isfinite(reference->signedDistance({0.1, 0.1, 0.1})));
    EXPECT_GT(reference->signedDistance({5, 5, 5}), 0.0);
}

// --- Analytic shapes -------------------------------------------------------------------------

TEST(CgalReference, GivesTheExactSdfOfABoxInsideOutsideAndAtCornersAndEdges) {
    const glm::dvec3 lo{-0.3, 0.2, 1.0}, hi{0.9, 0.65, 1.8};
    const TriangleSoup box = testmesh::boxSoup(lo, hi);
    const GridSpec grid = gridOf(box, 20, 4.5);
    const std::vector<glm::dvec3> points = gridPoints(grid);
    const double tolerance = 1e-9 * glm::length(hi - lo); // exact up to double rounding
    for (SignMode mode : {SignMode::Parity, SignMode::Winding}) {
        const CgalReference reference = referenceOf(box, mode);
        const std::vector<double> phi = reference.signedDistances(points);
        int inside = 0, outsideCornerRegion = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const double exact = testmesh::boxSdf(points[i], lo, hi);
            ASSERT_NEAR(phi[i], exact, tolerance) << "at " << i << " mode " << signModeName(mode);
            inside += exact < 0;
            const glm::dvec3 p = points[i];
            outsideCornerRegion += (p.x > hi.x && p.y > hi.y && p.z > hi.z);
        }
        EXPECT_GT(inside, 100);             // the test covers the inside ...
        EXPECT_GT(outsideCornerRegion, 20); // ... and the regions nearest a corner
    }
    // Single-point queries agree with the batch.
    const CgalReference reference = referenceOf(box, SignMode::Auto);
    for (const glm::dvec3& p :
         {glm::dvec3(0.3, 0.4, 1.4), glm::dvec3(2, 2, 3), glm::dvec3(0.9, 1, 2)})
        EXPECT_NEAR(reference.signedDistance(p), testmesh::boxSdf(p, lo, hi), tolerance);
}

TEST(CgalBake, MatchesTheSphereWithinItsTessellationError) {
    const glm::dvec3 center{0.25, -0.5, 1.0};
    const double radius = 0.8;
    const TriangleSoup sphere = testmesh::icoSphereSoup(center, radius, 4); // 5120 triangles
    const double tessellation = testmesh::sphereTessellationError(sphere, center, radius);
    ASSERT_GT(tessellation, 0.0);
    ASSERT_LT(tessellation, 2e-3 * radius); // about 0.03 voxels at this resolution
    const ImportedMesh mesh = testmesh::imported(sphere, "sphere");
    Result<format::ColliderAsset> asset = bakeCgal(mesh, {.grid = {.resolution = 40}});
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    EXPECT_EQ(asset->meta.bake.signUsed, format::SignMethod::Parity);

    // The polygon lies inside the sphere, so along the ray from the centre the polygon's and
    // the sphere's signed distances differ by at most the gap between them (the bound), plus
    // float storage.
    const double voxel = asset->meta.voxelSize;
    double worst = 0.0;
    for (std::uint32_t k = 0; k < asset->meta.dims.z; ++k)
        for (std::uint32_t j = 0; j < asset->meta.dims.y; ++j)
            for (std::uint32_t i = 0; i < asset->meta.dims.x; ++i) {
                const double exact =
                    testmesh::sphereSdf(asset->pointPosition(i, j, k), center, radius);
                const double error = std::abs(asset->distances[asset->index(i, j, k)] - exact);
                worst = std::max(worst, error);
            }
    EXPECT_LE(worst, tessellation + 1e-6 * radius)
        << "worst " << worst / voxel << " voxels, bound " << tessellation / voxel << " voxels";
    EXPECT_GT(worst, 0.1 * tessellation); // the bound is not vacuous: it is nearly reached
}

TEST(CgalBake, MatchesTheTorusWithinItsTessellationError) {
    const glm::dvec3 center{0.0, 0.1, -0.2};
    const double major = 1.0, minor = 0.35;
    const TriangleSoup torus = testmesh::torusSoup(center, major, minor, 96, 48);
    const double tessellation = testmesh::torusTessellationError(major, minor, 96, 48);
    const ImportedMesh mesh = testmesh::imported(torus, "torus");
    Result<format::ColliderAsset> asset = bakeCgal(mesh, {.grid = {.resolution = 40}});
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    const double voxel = asset->meta.voxelSize;
    ASSERT_LT(tessellation, 0.05 * voxel);

    // Where both agree on the side, the difference is at most the Hausdorff distance; in the
    // thin band between the two surfaces each distance is at most that band's width.
    double worstSameSide = 0.0, worstBand = 0.0;
    for (std::uint32_t k = 0; k < asset->meta.dims.z; ++k)
        for (std::uint32_t j = 0; j < asset->meta.dims.y; ++j)
            for (std::uint32_t i = 0; i < asset->meta.dims.x; ++i) {
                const double exact =
                    testmesh::torusSdf(asset->pointPosition(i, j, k), center, major, minor);
                const double phi = asset->distances[asset->index(i, j, k)];
                const double error = std::abs(phi - exact);
                if ((phi < 0) == (exact < 0))
                    worstSameSide = std::max(worstSameSide, error);
                else
                    worstBand = std::max(worstBand, error);
            }
    EXPECT_LE(worstSameSide, tessellation + 1e-6);
    EXPECT_LE(worstBand, 2 * tessellation + 1e-6);
}

TEST(TestMeshes, TorusTessellationBoundHoldsOnDenseSamplesBothWays) {
    // Checks the helper's bound (sum of the two sagittas) against measurement: polygon points
    // to the torus and torus points to the polygon.
    const double major = 1.0, minor = 0.35;
    const TriangleSoup torus = testmesh::torusSoup({0, 0, 0}, major, minor, 24, 12);
    const double bound = testmesh::torusTessellationError(major, minor, 24, 12);
    double polygonToTorus = 0.0;
    for (const glm::uvec3& t : torus.triangles)
        for (int a = 0; a <= 8; ++a)
            for (int b = 0; a + b <= 8; ++b) {
                const glm::dvec3 p = torus.positions[t.x] +
                                     (torus.positions[t.y] - torus.positions[t.x]) * (a / 8.0) +
                                     (torus.positions[t.z] - torus.positions[t.x]) * (b / 8.0);
                polygonToTorus = std::max(polygonToTorus,
                                          std::abs(testmesh::torusSdf(p, {0, 0, 0}, major, minor)));
            }
    double torusToPolygon = 0.0;
    for (int i = 0; i < 24 * 5; ++i)
        for (int j = 0; j < 12 * 5; ++j) {
            const double theta = 2 * std::numbers::pi * (i + 0.5) / (24 * 5);
            const double phi = 2 * std::numbers::pi * (j + 0.5) / (12 * 5);
            const double ring = major + minor * std::cos(phi);
            const glm::dvec3 p{ring * std::cos(theta), ring * std::sin(theta),
                               minor * std::sin(phi)};
            torusToPolygon = std::max(torusToPolygon, testmesh::bruteForceDistance(torus, p));
        }
    EXPECT_LE(polygonToTorus, bound);
    EXPECT_LE(torusToPolygon, bound);
    EXPECT_GT(std::max(polygonToTorus, torusToPolygon), 0.5 * bound); // and it is not loose
}

TEST(CgalReference, ParityAndWindingAgreeOnClosedMeshesAtEveryGridPoint) {
    for (const TriangleSoup& soup :
         {testmesh::boxSoup({0, 0, 0}, {1, 2, 0.5}), testmesh::icoSphereSoup({0, 0, 0}, 1.0, 3),
          testmesh::uvSphereSoup({1, 0, 0}, 0.5, 24, 12),
          testmesh::torusSoup({0, 0, 0}, 1.0, 0.3, 48, 24)}) {
        const std::vector<glm::dvec3> points = gridPoints(gridOf(soup, 32));
        const CgalReference parity = referenceOf(soup, SignMode::Parity);
        const CgalReference winding = referenceOf(soup, SignMode::Winding);
        ASSERT_EQ(parity.signMethod(), format::SignMethod::Parity);
        const std::vector<double> a = parity.signedDistances(points);
        const std::vector<double> b = winding.signedDistances(points);
        int negative = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            ASSERT_EQ(a[i], b[i]) << "at grid point " << i; // same distance, same sign
            negative += a[i] < 0;
        }
        EXPECT_GT(negative, 50);
    }
}

TEST(CgalReference, CarriedWindingNumberMatchesBruteForceOnOpenAndMessySoups) {
    // The winding sign is carried from point to point by exact crossing counts; compare it with
    // the brute-force generalized winding number at every grid point.
    TriangleSoup flipped = testmesh::icoSphereSoup({0, 0, 0}, 1.0, 2);
    for (std::size_t t = 0; t < flipped.triangles.size(); t += 3)
        std::swap(flipped.triangles[t].y, flipped.triangles[t].z); // inconsistent orientation
    TriangleSoup fan;
    fan.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, -1, 0}};
    fan.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
    const std::vector<std::pair<TriangleSoup, bool>> cases = {
        // soup, has a clear inside
        {testmesh::boxSoup({0, 0, 0}, {1, 1, 1}, true), true},
        {testmesh::uvSphereSoup({0, 0, 0}, 1.0, 32, 16, true), true},
        {testmesh::torusSoup({0, 0, 0}, 1.0, 0.4, 24, 12), true},
        {flipped, false},
        {fan, false}};
    for (std::size_t c = 0; c < cases.size(); ++c) {
        SCOPED_TRACE("case " + std::to_string(c));
        const auto& [soup, hasInside] = cases[c];
        const std::vector<glm::dvec3> points = gridPoints(gridOf(soup, 24));
        const CgalReference reference = referenceOf(soup, SignMode::Winding);
        const std::vector<double> phi = reference.signedDistances(points);
        int compared = 0, insideCount = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (phi[i] == 0.0)
                continue;
            const double w = reference.windingNumber(points[i]);
            if (std::abs(w - 0.5) < 1e-9)
                continue; // a tie either way is fine
            ASSERT_EQ(phi[i]<0, w> 0.5) << "grid point " << i << " w = " << w;
            ++compared;
            insideCount += w > 0.5;
        }
        // Points on the triangles (grid planes through the box faces, the fan) have no sign.
        EXPECT_GT(compared, int(points.size()) * 3 / 4);
        if (hasInside) {
            EXPECT_GT(insideCount, 10);
        }
    }
}

TEST(CgalBake, UsesTheWindingNumberOnAnOpenBoxWithTheSensibleSignAwayFromTheHole) {
    const glm::dvec3 lo{0, 0, 0}, hi{1, 1, 1};
    const ImportedMesh mesh = testmesh::imported(testmesh::boxSoup(lo, hi, true), "open-box");
    Result<format::ColliderAsset> asset = bakeCgal(mesh, {.grid = {.resolution = 20}});
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    EXPECT_EQ(asset->meta.bake.signUsed, format::SignMethod::Winding);
    // Well below the hole (the face z = 1) the closest points and the sign are the closed
    // box's, so its exact SDF holds; above the hole everything is outside.
    const double voxel = asset->meta.voxelSize;
    int below = 0, above = 0;
    for (std::uint32_t k = 0; k < asset->meta.dims.z; ++k)
        for (std::uint32_t j = 0; j < asset->meta.dims.y; ++j)
            for (std::uint32_t i = 0; i < asset->meta.dims.x; ++i) {
                const glm::dvec3 p = asset->pointPosition(i, j, k);
                const double phi = asset->distances[asset->index(i, j, k)];
                if (p.z < 0.5) {
                    ASSERT_NEAR(phi, testmesh::boxSdf(p, lo, hi), 1e-6)
                        << "at " << p.x << " " << p.y << " " << p.z;
                    ++below;
                } else if (p.z > 1.0 + 0.5 * voxel) {
                    ASSERT_GT(phi, 0.0) << "at " << p.x << " " << p.y << " " << p.z;
                    ++above;
                }
            }
    EXPECT_GT(below, 1000);
    EXPECT_GT(above, 1000);
}

TEST(CgalBake, GivesAnOpenHemisphereTheSignOfTheFullSphereAwayFromTheRim) {
    const TriangleSoup hemisphere = testmesh::uvSphereSoup({0, 0, 0}, 1.0, 48, 24, true);
    const CgalReference reference = referenceOf(hemisphere, SignMode::Auto);
    EXPECT_EQ(reference.signMethod(), format::SignMethod::Winding);
    EXPECT_LT(reference.signedDistance({0, 0, 0.8}), 0.0); // under the dome: w = 0.81
    EXPECT_LT(reference.signedDistance({0.3, 0.2, 0.5}), 0.0);
    EXPECT_GT(reference.signedDistance({0, 0, -0.5}), 0.0); // below the rim: w = 0.28
    EXPECT_GT(reference.signedDistance({0, 0, 1.5}), 0.0);
    EXPECT_GT(reference.signedDistance({3, 3, 3}), 0.0);
}

TEST(CgalBake, TurnsAnInwardWoundClosedMeshOutward) {
    TriangleSoup inward = testmesh::boxSoup({0, 0, 0}, {1, 1, 1});
    for (glm::uvec3& t : inward.triangles)
        std::swap(t.y, t.z);
    const CgalReference reference = referenceOf(inward, SignMode::Winding);
    EXPECT_NEAR(reference.signedDistance({0.5, 0.5, 0.4}), -0.4, 1e-12);
    EXPECT_NEAR(reference.signedDistance({0.5, 0.5, 1.4}), 0.4, 1e-12);
}

TEST(CgalBake, SkipsDegenerateTrianglesButCountsThem) {
    TriangleSoup box = testmesh::boxSoup({0, 0, 0}, {1, 1, 1});
    const Result<format::ColliderAsset> clean =
        bakeCgal(testmesh::imported(box), {.grid = {.resolution = 12}});
    box.positions.push_back({0.5, 0.5, 0.5});
    box.positions.push_back({0.7, 0.5, 0.5});
    box.triangles.push_back({8, 9, 8}); // repeated index, inside the box
    box.triangles.push_back({0, 1, 1});
    const ImportedMesh messy = testmesh::imported(box);
    EXPECT_EQ(messy.diagnostics.degenerateTriangles, 2u);
    const Result<format::ColliderAsset> asset = bakeCgal(messy, {.grid = {.resolution = 12}});
    ASSERT_TRUE(clean.ok() && asset.ok());
    EXPECT_EQ(asset->meta.mesh.degenerateTriangles, 2u);
    ASSERT_EQ(asset->distances.size(), clean->distances.size());
    EXPECT_EQ(std::memcmp(asset->distances.data(), clean->distances.data(),
                          clean->distances.size() * sizeof(float)),
              0);
}

// --- Provenance and determinism --------------------------------------------------------------

TEST(CgalBake, RecordsItsGridSettingsAndProvenanceInTheAsset) {
    ImportedMesh mesh =
        testmesh::imported(testmesh::torusSoup({0, 0, 0}, 1.0, 0.3, 24, 12), "torus.obj");
    mesh.sourceHash = "0123456789abcdef";
    const BakeSettings settings{.grid = {.resolution = 24, .padding = 2.5},
                                .sign = SignMode::Winding,
                                .storage = format::Storage::F16,
                                .scale = 2.0};
    Result<format::ColliderAsset> asset = bakeCgal(mesh, settings);
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    const format::ColliderMeta& meta = asset->meta;
    const GridSpec grid = *gridFor(mesh.soup.bounds(), settings.grid);
    EXPECT_EQ(meta.dims, grid.dims);
    EXPECT_EQ(meta.origin, grid.origin);
    EXPECT_EQ(meta.voxelSize, grid.voxelSize);
    EXPECT_EQ(asset->distances.size(), asset->pointCount());
    EXPECT_EQ(meta.storage, format::Storage::F16);
    EXPECT_EQ(meta.signConvention, -1);
    EXPECT_EQ(meta.sourceFile, "torus.obj");
    EXPECT_EQ(meta.sourceHash, "0123456789abcdef");
    EXPECT_EQ(meta.bake.backend, "cgal");
    EXPECT_EQ(meta.bake.resolution, 24u);
    EXPECT_EQ(meta.bake.padding, 2.5);
    EXPECT_EQ(meta.bake.signMode, "winding");
    EXPECT_EQ(meta.bake.signUsed, format::SignMethod::Winding);
    EXPECT_EQ(meta.bake.scale, 2.0);
    EXPECT_EQ(meta.toolVersion.rfind("sluice-bake ", 0), 0u) << meta.toolVersion;
    EXPECT_GT(meta.toolVersion.size(), std::string("sluice-bake ").size());
    EXPECT_EQ(meta.mesh.triangles, mesh.diagnostics.triangles);
    EXPECT_EQ(meta.mesh.vertices, mesh.diagnostics.vertices);
    EXPECT_TRUE(meta.mesh.closed);
    EXPECT_FALSE(meta.validation.known);

    Result<format::ColliderAsset> byVoxel =
        bakeCgal(mesh, {.grid = {.resolution = 24, .voxelSize = 0.1}});
    ASSERT_TRUE(byVoxel.ok());
    EXPECT_EQ(byVoxel->meta.bake.resolution, 0u); // the voxel size was given instead
    EXPECT_EQ(byVoxel->meta.voxelSize, 0.1);
}

TEST(CgalBake, GivesBitwiseIdenticalDistancesOnEveryRunAndThreadCount) {
    // An open, messy soup exercises the carried winding number, the most order-sensitive path.
    TriangleSoup soup = testmesh::uvSphereSoup({0, 0, 0}, 1.0, 40, 20, true);
    const TriangleSoup torus = testmesh::torusSoup({0.2, 0, 0.3}, 0.8, 0.25, 32, 16);
    const std::uint32_t offset = std::uint32_t(soup.positions.size());
    soup.positions.insert(soup.positions.end(), torus.positions.begin(), torus.positions.end());
    for (const glm::uvec3& t : torus.triangles)
        soup.triangles.push_back(t + offset); // the torus cuts through the dome
    const ImportedMesh mesh = testmesh::imported(soup);
    EXPECT_TRUE(mesh.diagnostics.selfIntersecting);
    const BakeSettings settings{.grid = {.resolution = 28}};
    Result<format::ColliderAsset> first = bakeCgal(mesh, settings);
    Result<format::ColliderAsset> second = bakeCgal(mesh, settings);
    Result<format::ColliderAsset> serial = [&] {
        tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
        return bakeCgal(mesh, settings);
    }();
    ASSERT_TRUE(first.ok() && second.ok() && serial.ok());
    const std::size_t bytes = first->distances.size() * sizeof(float);
    EXPECT_EQ(std::memcmp(first->distances.data(), second->distances.data(), bytes), 0);
    EXPECT_EQ(std::memcmp(first->distances.data(), serial->distances.data(), bytes), 0);
}

// --- Progress --------------------------------------------------------------------------------

TEST(Progress, CountsWorkFromManyThreadsAndReportsItsRate) {
    Progress progress("count", 4000, false);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&] {
            for (int i = 0; i < 1000; ++i)
                progress.add(1);
        });
    for (std::thread& t : threads)
        t.join();
    const double rate = progress.finish();
    EXPECT_GT(rate, 0.0);
    EXPECT_EQ(progress.finish(), rate); // finishing twice changes nothing
}

TEST(Progress, StaysSilentForShortWorkAndDrawsTenLinesAndARateForLongWork) {
    testing::internal::CaptureStderr();
    {
        Progress quick("quick", 10);
        quick.add(10);
    }
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");

    testing::internal::CaptureStderr();
    Progress slow("slow", 100);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    for (int i = 0; i < 100; ++i)
        slow.add(1);
    slow.finish();
    const std::string out = testing::internal::GetCapturedStderr();
    EXPECT_NE(out.find("slow"), std::string::npos);
    EXPECT_NE(out.find("100 %"), std::string::npos) << out; // not a terminal: a line per 10 %
    EXPECT_NE(out.find("voxels/s"), std::string::npos) << out;
}

} // namespace
