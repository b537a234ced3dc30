// Polyhedral mass properties (MeshMass.h) against the closed forms of boxes and spheres.
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <gtest/gtest.h>

#include "import/MeshMass.h"
#include "TestMeshes.h"

namespace {

using namespace sluice;
using namespace sluice::bake;

/// Inertia about the centre of a solid box with sides `size`, unit density (diagonal).
glm::dmat3 boxInertia(const glm::dvec3& size) {
    const double volume = size.x * size.y * size.z;
    const glm::dvec3 sq = size * size;
    glm::dmat3 inertia(0.0);
    inertia[0][0] = volume * (sq.y + sq.z) / 12.0;
    inertia[1][1] = volume * (sq.x + sq.z) / 12.0;
    inertia[2][2] = volume * (sq.x + sq.y) / 12.0;
    return inertia;
}

/// Expects every element of `actual` within `relative` * |expected|_F of `expected`.
void expectMatrixNear(const glm::dmat3& actual, const glm::dmat3& expected, double relative) {
    const double tolerance = relative * testmesh::frobenius(expected);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(actual[c][r], expected[c][r], tolerance) << "row " << r << " column " << c;
}

TEST(MeshMass, AnAxisAlignedBoxGivesItsExactVolumeCentreAndDiagonalInertia) {
    const glm::dvec3 lo(1.0, 2.0, 3.0), hi(3.0, 5.0, 7.0); // sides 2 x 3 x 4
    const format::MassProperties mass = polyhedronMassProperties(testmesh::boxSoup(lo, hi));
    EXPECT_NEAR(mass.volume, 24.0, 24.0 * 1e-12);
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(mass.centerOfMass[a], 0.5 * (lo[a] + hi[a]), 1e-12 * 7.0) << "axis " << a;
    const glm::dmat3 expected = boxInertia(hi - lo); // diagonal 50, 40, 26
    EXPECT_NEAR(mass.inertia[0][0], 50.0, 50.0 * 1e-12);
    EXPECT_NEAR(mass.inertia[1][1], 40.0, 40.0 * 1e-12);
    EXPECT_NEAR(mass.inertia[2][2], 26.0, 26.0 * 1e-12);
    expectMatrixNear(mass.inertia, expected, 1e-12);
}

TEST(MeshMass, AnInwardFacingBoxGivesTheSamePositiveProperties) {
    const glm::dvec3 lo(-1.0, 0.5, 2.0), hi(0.5, 1.0, 4.5);
    TriangleSoup flipped = testmesh::boxSoup(lo, hi);
    for (glm::uvec3& t : flipped.triangles)
        std::swap(t.y, t.z);
    ASSERT_LT(testmesh::signedVolume(flipped), 0.0);
    const format::MassProperties outward = polyhedronMassProperties(testmesh::boxSoup(lo, hi));
    const format::MassProperties inward = polyhedronMassProperties(flipped);
    const double volume = 1.5 * 0.5 * 2.5;
    EXPECT_NEAR(inward.volume, volume, volume * 1e-12);
    EXPECT_NEAR(glm::length(inward.centerOfMass - 0.5 * (lo + hi)), 0.0, 1e-12 * 4.5);
    expectMatrixNear(inward.inertia, boxInertia(hi - lo), 1e-12);
    EXPECT_NEAR(inward.volume, outward.volume, volume * 1e-14);
    expectMatrixNear(inward.inertia, outward.inertia, 1e-14);
    // The bake keeps it too: orientation is a matter of winding, not of the solid.
    const std::optional<format::MassProperties> kept =
        closedMeshMass(flipped, bake::diagnose(flipped));
    ASSERT_TRUE(kept.has_value());
    EXPECT_NEAR(kept->volume, volume, volume * 1e-12);
}

TEST(MeshMass, ARotatedAndTranslatedBoxHasItsInertiaTensorRotated) {
    const glm::dvec3 size(2.0, 0.75, 1.25);
    const TriangleSoup local = testmesh::boxSoup(-0.5 * size, 0.5 * size);
    // R = a rotation about an oblique axis, then a translation far from the origin.
    const glm::dmat4 rotation4 =
        glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1.0, 2.0, -0.5)));
    const glm::dmat3 rotation(rotation4);
    const glm::dvec3 translation(40.0, -25.0, 12.5);
    TriangleSoup placed = local;
    for (glm::dvec3& p : placed.positions)
        p = rotation * p + translation;

    const format::MassProperties mass = polyhedronMassProperties(placed);
    const double volume = size.x * size.y * size.z;
    EXPECT_NEAR(mass.volume, volume, volume * 1e-12);
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(mass.centerOfMass[a], translation[a], 1e-12 * 50.0) << "axis " << a;
    // I' = R I R^T, with off-diagonal terms now.
    const glm::dmat3 expected = rotation * boxInertia(size) * glm::transpose(rotation);
    ASSERT_GT(std::abs(expected[0][1]), 0.01 * testmesh::frobenius(expected));
    expectMatrixNear(mass.inertia, expected, 1e-12);
    // Exactly symmetric, as the asset reader requires.
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            EXPECT_EQ(mass.inertia[c][r], mass.inertia[r][c]);
}

TEST(MeshMass, AFinelyTessellatedSphereIsWithinItsTessellationErrorOfTheBall) {
    const glm::dvec3 center(0.3, -0.2, 0.1);
    const double radius = 1.5;
    const TriangleSoup sphere = testmesh::icoSphereSoup(center, radius, 5); // 20480 triangles
    // The polyhedron holds the ball of radius r - e and lies in the ball of radius r: its volume
    // and (positive) diagonal inertia lie between those of the two balls.
    const double e = testmesh::sphereTessellationError(sphere, center, radius);
    ASSERT_GT(e, 0.0);
    ASSERT_LT(e, 1e-3 * radius);
    auto ballVolume = [](double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; };
    auto ballInertia = [&](double r) { return 0.4 * ballVolume(r) * r * r; };

    const format::MassProperties mass = polyhedronMassProperties(sphere);
    EXPECT_GE(mass.volume, ballVolume(radius - e));
    EXPECT_LE(mass.volume, ballVolume(radius));
    // Symmetric under x -> -x about the centre, and isotropic (icosahedral symmetry).
    EXPECT_NEAR(glm::length(mass.centerOfMass - center), 0.0, 1e-12 * radius);
    for (int a = 0; a < 3; ++a) {
        EXPECT_GE(mass.inertia[a][a], ballInertia(radius - e)) << "axis " << a;
        EXPECT_LE(mass.inertia[a][a], ballInertia(radius)) << "axis " << a;
        for (int b = 0; b < 3; ++b) {
            if (a == b)
                continue;
            EXPECT_NEAR(mass.inertia[a][b], 0.0, 1e-12 * mass.inertia[0][0]);
        }
    }
}

TEST(MeshMass, TheCornerTetrahedronHasItsKnownProductsOfInertia) {
    // Corners 0, x, y, z: volume 1/6, centre 1/4; int x^2 = 1/60, int xy = 1/120 about the
    // origin, so about the centre Ixx = 2 (1/60 - 1/96) = 1/80 and Ixy = 1/96 - 1/120 = 1/480.
    TriangleSoup tetra;
    tetra.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const format::MassProperties mass = polyhedronMassProperties(tetra);
    EXPECT_NEAR(mass.volume, 1.0 / 6.0, 1e-15);
    EXPECT_NEAR(glm::length(mass.centerOfMass - glm::dvec3(0.25)), 0.0, 1e-15);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(mass.inertia[c][r], r == c ? 1.0 / 80.0 : 1.0 / 480.0, 1e-15)
                << "row " << r << " column " << c;
}

TEST(MeshMass, OpenOrInconsistentlyWoundMeshesGetNone) {
    const TriangleSoup open = testmesh::boxSoup({0, 0, 0}, {1, 1, 1}, /*withoutTop=*/true);
    EXPECT_FALSE(closedMeshMass(open, bake::diagnose(open)).has_value());

    // Closed, but one face's two triangles wound inward: the integrals would be wrong.
    TriangleSoup mixed = testmesh::boxSoup({0, 0, 0}, {1, 1, 1});
    std::swap(mixed.triangles[0].y, mixed.triangles[0].z);
    std::swap(mixed.triangles[1].y, mixed.triangles[1].z);
    ASSERT_TRUE(bake::diagnose(mixed).closed);
    EXPECT_FALSE(closedMeshMass(mixed, bake::diagnose(mixed)).has_value());

    const TriangleSoup closed = testmesh::boxSoup({0, 0, 0}, {1, 1, 1});
    const std::optional<format::MassProperties> mass = closedMeshMass(closed, diagnose(closed));
    ASSERT_TRUE(mass.has_value());
    EXPECT_NEAR(mass->volume, 1.0, 1e-12);
}

} // namespace
