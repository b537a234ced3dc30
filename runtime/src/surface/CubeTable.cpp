// Building the cell triangle table once, on the CPU: for each inside pattern, the segments each
// face cuts, chained into the cell's polygons, each split into triangles.
#include "surface/CubeTable.h"

#include <functional>
#include <map>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "sluice/format/support/Assert.h"

namespace sluice::rt {
namespace {

glm::vec3 corner(std::uint32_t c) {
    return glm::vec3(float(c & 1u), float((c >> 1) & 1u), float((c >> 2) & 1u));
}

/// The edge between corners a and b that differ in one axis: its code (lower corner in bits
/// 0-2, the axis bit in bits 3-5).
std::uint32_t edgeCode(std::uint32_t a, std::uint32_t b) {
    return (a & b) | ((a ^ b) << 3);
}

glm::vec3 midpoint(std::uint32_t edge) {
    return corner(edge & 7u) + 0.5f * corner(edge >> 3);
}

/// Whether two edges lie on a common face (an edge lies on the two faces across the axes it
/// does not run along).
bool shareFace(std::uint32_t e, std::uint32_t f) {
    for (std::uint32_t axis = 0; axis < 3; ++axis) {
        const std::uint32_t bit = 1u << axis;
        if ((e >> 3) != bit && (f >> 3) != bit && ((e & 7u) & bit) == ((f & 7u) & bit))
            return true;
    }
    return false;
}

struct Face {
    std::uint32_t cycle[4]; ///< corners in order round the face
    glm::vec3 outward;      ///< out of the cell
};

std::vector<Face> cellFaces() {
    std::vector<Face> faces;
    for (std::uint32_t a = 0; a < 3; ++a) {
        const std::uint32_t b = (a + 1) % 3, c = (a + 2) % 3;
        for (std::uint32_t side = 0; side < 2; ++side) {
            Face f{};
            f.outward = glm::vec3(0.0f);
            const std::uint32_t uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int i = 0; i < 4; ++i)
                f.cycle[i] = (side << a) | (uv[i][0] << b) | (uv[i][1] << c);
            f.outward[a] = side != 0 ? 1.0f : -1.0f;
            faces.push_back(f);
        }
    }
    return faces;
}

/// The segments the surface cuts across the faces of a cell with inside corners `mask`, as
/// (from, to) edge codes, oriented so that the cell's polygons come out counter-clockwise seen
/// from outside. A face with two crossed edges has one segment; one with four (two opposite
/// corners inside, two outside) cuts off its two outside corners, so the inside stays joined
/// across it. Either rule is consistent; this one keeps thin sheets of fluid whole. The cut
/// depends on the face's four corners alone, so the cell on the other side makes the same.
std::vector<std::pair<std::uint32_t, std::uint32_t>> faceSegments(std::uint32_t mask) {
    static const std::vector<Face> faces = cellFaces();
    const auto inside = [mask](std::uint32_t c) { return ((mask >> c) & 1u) != 0; };
    std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;
    for (const Face& f : faces) {
        std::vector<std::uint32_t> crossed;
        for (int i = 0; i < 4; ++i)
            if (inside(f.cycle[i]) != inside(f.cycle[(i + 1) % 4]))
                crossed.push_back(edgeCode(f.cycle[i], f.cycle[(i + 1) % 4]));
        std::vector<std::pair<std::uint32_t, std::uint32_t>> cut;
        if (crossed.size() == 2)
            cut.emplace_back(crossed[0], crossed[1]);
        else if (crossed.size() == 4)
            for (int i = 0; i < 4; ++i)
                if (!inside(f.cycle[i]))
                    cut.emplace_back(edgeCode(f.cycle[(i + 3) % 4], f.cycle[i]),
                                     edgeCode(f.cycle[i], f.cycle[(i + 1) % 4]));
        for (auto [u, v] : cut) {
            // The inside ends of the two edges; the segment runs with them on its right, seen
            // from outside the cell.
            glm::vec3 in(0.0f);
            float count = 0.0f;
            for (std::uint32_t e : {u, v})
                for (std::uint32_t c : {e & 7u, (e & 7u) | (e >> 3)})
                    if (inside(c)) {
                        in += corner(c);
                        count += 1.0f;
                    }
            const glm::vec3 from = midpoint(u);
            if (glm::dot(glm::cross(f.outward, midpoint(v) - from), in / count - from) > 0.0f)
                std::swap(u, v);
            segments.emplace_back(u, v);
        }
    }
    return segments;
}

/// Splits the polygon `p` (edge codes, in order) into triangles whose diagonals join only
/// vertices on edges with no face in common: a diagonal across a face would be the neighbouring
/// cell's edge too, and four triangles would meet at it. False if there is no such split.
bool triangulate(const std::vector<std::uint32_t>& p, std::vector<std::uint32_t>& out) {
    const auto diagonalOk = [&](std::size_t i, std::size_t j) {
        return j - i == 1 || (i == 0 && j == p.size() - 1) || !shareFace(p[i], p[j]);
    };
    // The chain p[i..j] closed by the side or diagonal (i, j): a triangle (i, k, j) and the two
    // chains it leaves.
    std::function<bool(std::size_t, std::size_t)> split = [&](std::size_t i, std::size_t j) {
        if (j - i < 2)
            return true;
        for (std::size_t k = i + 1; k < j; ++k) {
            if (!diagonalOk(i, k) || !diagonalOk(k, j))
                continue;
            const std::size_t before = out.size();
            if (split(i, k) && split(k, j)) {
                out.push_back(p[i] | (p[k] << 6) | (p[j] << 12) | (1u << 31));
                return true;
            }
            out.resize(before);
        }
        return false;
    };
    return split(0, p.size() - 1);
}

CellTriangleTable build() {
    CellTriangleTable table{};
    for (std::uint32_t mask = 0; mask < 256; ++mask) {
        std::map<std::uint32_t, std::uint32_t> next;
        for (auto [u, v] : faceSegments(mask)) {
            SLUICE_ASSERT(next.count(u) == 0, "CubeTable: an edge starts two segments");
            next[u] = v;
        }
        std::vector<std::uint32_t> triangles;
        while (!next.empty()) {
            std::vector<std::uint32_t> polygon;
            for (std::uint32_t e = next.begin()->first; next.count(e) != 0;) {
                polygon.push_back(e);
                const std::uint32_t to = next[e];
                next.erase(e);
                e = to;
            }
            SLUICE_ASSERT(polygon.size() >= 3, "CubeTable: a polygon of under three edges");
            const bool split = triangulate(polygon, triangles);
            SLUICE_ASSERT(split, "CubeTable: a polygon without a manifold split");
        }
        SLUICE_ASSERT(triangles.size() <= kCellTrianglesMax, "CubeTable: too many triangles");
        for (std::size_t k = 0; k < triangles.size(); ++k)
            table[mask * kCellTrianglesMax + k] = triangles[k];
        table[256 * kCellTrianglesMax + mask] = std::uint32_t(triangles.size());
    }
    return table;
}

} // namespace

const CellTriangleTable& cellTriangleTable() {
    static const CellTriangleTable table = build();
    return table;
}

} // namespace sluice::rt
