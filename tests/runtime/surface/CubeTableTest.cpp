// The marching-cubes cell table (runtime/src/surface/CubeTable.cpp), on the CPU: extracted over
// random grids of inside and outside samples, its meshes are closed, manifold and face out.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "MeshTopology.h"
#include "sluice/rt/surface/SurfaceMesh.h"
#include "surface/CubeTable.h"

namespace sluice::rt {
namespace {

using namespace surfacetest;

/// The mesh the cell triangle table gives over a grid of inside (true) and outside samples,
/// on the CPU: one vertex at the middle of every crossed edge, shared by the cells round it.
SurfaceMesh tableMesh(const std::vector<bool>& inside, int n,
                      std::set<std::uint32_t>* cases = nullptr) {
    const auto at = [&](glm::ivec3 s) { return bool(inside[s.x + n * (s.y + n * s.z)]); };
    const auto offset = [](std::uint32_t c) { return glm::ivec3(c & 1u, (c >> 1) & 1u, c >> 2); };
    SurfaceMesh mesh;
    std::map<std::pair<int, std::uint32_t>, std::uint32_t> vertexOf; // (sample, axis bit)
    const CellTriangleTable& table = cellTriangleTable();
    for (int z = 0; z + 1 < n; ++z)
        for (int y = 0; y + 1 < n; ++y)
            for (int x = 0; x + 1 < n; ++x) {
                const glm::ivec3 s(x, y, z);
                std::uint32_t mask = 0;
                for (std::uint32_t c = 0; c < 8; ++c)
                    mask |= std::uint32_t(at(s + offset(c))) << c;
                if (cases)
                    cases->insert(mask);
                std::uint32_t count = 0;
                for (std::size_t k = 0; k < kCellTrianglesMax; ++k) {
                    const std::uint32_t t = table[mask * kCellTrianglesMax + k];
                    if (t == 0)
                        break;
                    ++count;
                    glm::uvec3 tri;
                    for (int v = 0; v < 3; ++v) {
                        const std::uint32_t edge = (t >> (6 * v)) & 63u;
                        const glm::ivec3 lo = s + offset(edge & 7u);
                        const std::uint32_t axis = edge >> 3;
                        EXPECT_TRUE(axis == 1 || axis == 2 || axis == 4) << "edge " << edge;
                        const auto [it, added] = vertexOf.try_emplace(
                            {lo.x + n * (lo.y + n * lo.z), axis}, std::uint32_t(vertexOf.size()));
                        if (added)
                            mesh.vertices.push_back(glm::vec3(lo) + 0.5f * glm::vec3(offset(axis)));
                        tri[v] = it->second;
                    }
                    mesh.triangles.push_back(tri);
                }
                EXPECT_EQ(count, table[256 * kCellTrianglesMax + mask]) << "case " << mask;
            }
    return mesh;
}

// Marching cubes with the faces cut by their own corners alone: on random grids, with every
// ambiguous face and cell the fill fractions make, the mesh is closed and manifold and faces
// out (positive volume); one inside sample gives the octahedron round it.
TEST(CubeTable, GivesClosedManifoldOutwardMeshesOnRandomGrids) {
    const int n = 7;
    std::vector<bool> inside(n * n * n, false);
    inside[3 + n * (3 + n * 3)] = true;
    const SurfaceMesh single = tableMesh(inside, n);
    EXPECT_EQ(single.triangles.size(), 8u);
    EXPECT_NEAR(meshVolume(single), 1.0 / 6.0, 1e-9);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::size_t triangles = 0;
    std::set<std::uint32_t> cases;
    for (int trial = 0; trial < 400; ++trial) {
        const double fill = 0.1 + 0.8 * uniform(random);
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const bool border = std::min({x, y, z}) == 0 || std::max({x, y, z}) == n - 1;
                    inside[x + n * (y + n * z)] = !border && uniform(random) < fill;
                }
        const SurfaceMesh mesh = tableMesh(inside, n, &cases);
        const Topology t = topology(mesh);
        ASSERT_EQ(t.badTriangles + t.openEdges + t.repeatedEdges + t.pinchedVertices, 0u)
            << "trial " << trial << ": bad " << t.badTriangles << ", open " << t.openEdges
            << ", repeated " << t.repeatedEdges << ", pinched " << t.pinchedVertices;
        EXPECT_GT(meshVolume(mesh), 0.0) << "trial " << trial;
        triangles += mesh.triangles.size();
    }
    EXPECT_GT(triangles, 40000u);
    EXPECT_EQ(cases.size(), 256u) << "every inside pattern of a cell met";
}

} // namespace
} // namespace sluice::rt
