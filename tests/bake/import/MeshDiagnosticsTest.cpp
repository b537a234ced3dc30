// The mesh diagnostics: closed, boundary edges, non-manifold, degenerate and self-intersecting
// triangles, on soups whose answers are known.
#include <gtest/gtest.h>

#include "TestMeshes.h"
#include "sluice/bake/import/MeshImport.h"

namespace {

using namespace sluice;
using namespace sluice::bake;

/// The unit box and `other` in one soup (box corners 0..7, then other's).
TriangleSoup unitBoxAnd(const TriangleSoup& other) {
    TriangleSoup soup = testmesh::boxSoup({0, 0, 0}, {1, 1, 1});
    for (const glm::uvec3& t : other.triangles)
        soup.triangles.push_back(t + 8u);
    soup.positions.insert(soup.positions.end(), other.positions.begin(), other.positions.end());
    return soup;
}

// --- Diagnostics -----------------------------------------------------------------------------

TEST(MeshDiagnostics, FindsAClosedBoxClosedAndClean) {
    const format::MeshDiagnostics d = diagnose(testmesh::boxSoup({0, 0, 0}, {1, 1, 1}));
    EXPECT_EQ(d.triangles, 12u);
    EXPECT_EQ(d.vertices, 8u);
    EXPECT_EQ(d.degenerateTriangles, 0u);
    EXPECT_EQ(d.boundaryEdges, 0u);
    EXPECT_EQ(d.nonManifoldEdges, 0u);
    EXPECT_TRUE(d.closed);
    EXPECT_FALSE(d.selfIntersecting);
}

TEST(MeshDiagnostics, CountsTheFourRimEdgesOfAnOpenBox) {
    const format::MeshDiagnostics d = diagnose(testmesh::boxSoup({0, 0, 0}, {1, 1, 1}, true));
    EXPECT_EQ(d.triangles, 10u);
    EXPECT_EQ(d.boundaryEdges, 4u);
    EXPECT_EQ(d.nonManifoldEdges, 0u);
    EXPECT_FALSE(d.closed);
    EXPECT_FALSE(d.selfIntersecting);
}

TEST(MeshDiagnostics, CountsAnEdgeSharedByThreeTrianglesAsNonManifold) {
    TriangleSoup fan;
    fan.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, -1, 0}};
    fan.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
    const format::MeshDiagnostics d = diagnose(fan);
    EXPECT_EQ(d.nonManifoldEdges, 1u);
    EXPECT_EQ(d.boundaryEdges, 6u);
    EXPECT_FALSE(d.closed);
    EXPECT_FALSE(d.selfIntersecting); // they only share the edge
}

TEST(MeshDiagnostics, CountsRepeatedIndexAndZeroAreaTrianglesAsDegenerate) {
    TriangleSoup soup = testmesh::boxSoup({0, 0, 0}, {1, 1, 1});
    soup.positions.push_back({0.5, 0.0, 0.0}); // on the edge from corner 0 to corner 1
    soup.triangles.push_back({0, 0, 1});       // repeated index
    soup.triangles.push_back({0, 8, 1});       // three distinct corners on one line
    const format::MeshDiagnostics d = diagnose(soup);
    EXPECT_EQ(d.triangles, 14u);
    EXPECT_EQ(d.degenerateTriangles, 2u);
    // The sliver adds edges 0-8 and 8-1 once each and edge 0-1 a third time.
    EXPECT_EQ(d.boundaryEdges, 2u);
    EXPECT_EQ(d.nonManifoldEdges, 1u);
    EXPECT_FALSE(d.selfIntersecting); // degenerate triangles are counted, not intersected
}

TEST(MeshDiagnostics, FindsTwoOverlappingBoxesSelfIntersecting) {
    const TriangleSoup soup = unitBoxAnd(testmesh::boxSoup({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5}));
    EXPECT_TRUE(diagnose(soup).selfIntersecting);
    EXPECT_TRUE(diagnose(soup).closed); // two closed shells: every edge used twice
}

TEST(MeshDiagnostics, FindsTwoSeparateBoxesNotSelfIntersecting) {
    const TriangleSoup soup = unitBoxAnd(testmesh::boxSoup({2, 0, 0}, {3, 1, 1}));
    EXPECT_FALSE(diagnose(soup).selfIntersecting);
}

TEST(MeshDiagnostics, FindsCoplanarTrianglesFoldedOverASharedEdgeSelfIntersecting) {
    TriangleSoup soup;
    soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 1, 0}};
    soup.triangles = {{0, 1, 2}, {1, 0, 3}}; // both on the same side of edge 0-1, overlapping
    EXPECT_TRUE(diagnose(soup).selfIntersecting);
    soup.positions[3] = {0.5, -1, 0}; // now on the other side: a flat, clean pair
    EXPECT_FALSE(diagnose(soup).selfIntersecting);
}

TEST(MeshDiagnostics, FindsTrianglesCrossingAtASharedVertexSelfIntersecting) {
    TriangleSoup soup;
    soup.positions = {{0, 0, 0}, {2, -1, 0}, {2, 1, 0}, {1, 0, -1}, {1, 0, 1}};
    soup.triangles = {{0, 1, 2}, {0, 3, 4}}; // the second pierces the first through its inside
    EXPECT_TRUE(diagnose(soup).selfIntersecting);
    soup.positions[3] = {-1, 0, -1};
    soup.positions[4] = {-1, 0, 1}; // now it points away: they share only the vertex
    EXPECT_FALSE(diagnose(soup).selfIntersecting);
}

TEST(MeshDiagnostics, FindsTheTessellatedSphereAndTorusClosedAndClean) {
    for (const TriangleSoup& soup : {testmesh::icoSphereSoup({0, 0, 0}, 1.0, 3),
                                     testmesh::uvSphereSoup({0, 0, 0}, 1.0, 24, 12),
                                     testmesh::torusSoup({0, 0, 0}, 1.0, 0.3, 32, 16)}) {
        const format::MeshDiagnostics d = diagnose(soup);
        EXPECT_TRUE(d.closed);
        EXPECT_FALSE(d.selfIntersecting);
        EXPECT_EQ(d.degenerateTriangles, 0u);
        EXPECT_GT(testmesh::signedVolume(soup), 0.0); // the helpers wind outward
    }
    const format::MeshDiagnostics hemisphere =
        diagnose(testmesh::uvSphereSoup({0, 0, 0}, 1.0, 24, 12, true));
    EXPECT_EQ(hemisphere.boundaryEdges, 24u);
    EXPECT_FALSE(hemisphere.closed);
}

} // namespace
