// Closed-and-manifold checks of triangle meshes shared by the surface tests: the enclosed volume,
// the edge and vertex-fan topology, and the expectation a reconstructed surface must meet.
#ifndef SLUICE_TESTS_RUNTIME_SURFACE_MESHTOPOLOGY_H
#define SLUICE_TESTS_RUNTIME_SURFACE_MESHTOPOLOGY_H

#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::rt::surfacetest {

/// The enclosed volume by the divergence theorem [m^3] (positive for outward triangles).
inline double meshVolume(const SurfaceMesh& mesh) {
    double volume = 0.0;
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::dvec3 a(mesh.vertices[t.x]), b(mesh.vertices[t.y]), c(mesh.vertices[t.z]);
        volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return volume;
}

/// What makes a mesh closed and manifold: every triangle has three distinct vertices, every
/// directed edge appears once and its reverse once (so every edge has exactly two triangles,
/// oriented alike), every vertex is used, and the triangles around each vertex form one fan.
struct Topology {
    std::size_t badTriangles = 0;  ///< repeated vertex in a triangle
    std::size_t openEdges = 0;     ///< directed edges without their reverse
    std::size_t repeatedEdges = 0; ///< directed edges used twice (flipped or non-manifold)
    std::size_t unusedVertices = 0;
    std::size_t pinchedVertices = 0; ///< vertices whose triangles form more than one fan
    long euler = 0;                  ///< V - E + F
};

inline Topology topology(const SurfaceMesh& mesh) {
    Topology t;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> fans(mesh.vertices.size());
    for (const glm::uvec3& tri : mesh.triangles) {
        if (tri.x == tri.y || tri.y == tri.z || tri.x == tri.z) {
            ++t.badTriangles;
            continue;
        }
        const std::uint32_t v[3] = {tri.x, tri.y, tri.z};
        for (int k = 0; k < 3; ++k) {
            ++directed[{v[k], v[(k + 1) % 3]}];
            fans[v[k]].emplace_back(v[(k + 1) % 3], v[(k + 2) % 3]); // the opposite edge
        }
    }
    std::size_t edges = 0;
    for (const auto& [edge, count] : directed) {
        t.repeatedEdges += count > 1;
        const bool reverse = directed.count({edge.second, edge.first}) > 0;
        t.openEdges += !reverse;
        edges += reverse && edge.first < edge.second;
    }
    for (std::size_t v = 0; v < fans.size(); ++v) {
        if (fans[v].empty()) {
            ++t.unusedVertices;
            continue;
        }
        // Walk the ring of opposite edges from one of them: it must close over all of them.
        std::map<std::uint32_t, std::uint32_t> next;
        for (const auto& [a, b] : fans[v])
            next[a] = b;
        std::uint32_t at = fans[v][0].first;
        std::size_t steps = 0;
        do {
            const auto it = next.find(at);
            if (it == next.end())
                break;
            at = it->second;
            ++steps;
        } while (at != fans[v][0].first && steps <= fans[v].size());
        t.pinchedVertices += steps != fans[v].size();
    }
    t.euler = long(mesh.vertices.size()) - long(edges) + long(mesh.triangles.size());
    return t;
}

inline void expectClosedManifold(const SurfaceMesh& mesh, long euler) {
    const Topology t = topology(mesh);
    EXPECT_GT(mesh.triangles.size(), 100u);
    EXPECT_EQ(t.badTriangles, 0u);
    EXPECT_EQ(t.openEdges, 0u);
    EXPECT_EQ(t.repeatedEdges, 0u);
    EXPECT_EQ(t.unusedVertices, 0u);
    EXPECT_EQ(t.pinchedVertices, 0u);
    EXPECT_EQ(t.euler, euler) << "V - E + F of one closed surface of genus " << (2 - euler) / 2;
    for (const glm::vec3& n : mesh.normals)
        ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f);
}

} // namespace sluice::rt::surfacetest

#endif // SLUICE_TESTS_RUNTIME_SURFACE_MESHTOPOLOGY_H
