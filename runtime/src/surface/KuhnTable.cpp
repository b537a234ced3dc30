// Building the cell triangle table once, on the CPU.
#include "surface/KuhnTable.h"

#include <glm/glm.hpp>

namespace sluice::rt {
namespace {

// The six tetrahedra: corners 0, e_a, e_a + e_b, 7 for every order a, b of two axes.
constexpr std::uint32_t kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                       {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

glm::vec3 corner(std::uint32_t c) {
    return glm::vec3(float(c & 1u), float((c >> 1) & 1u), float((c >> 2) & 1u));
}

/// An edge between corners a and b, one of which holds the other's bits.
std::uint32_t edgeCode(std::uint32_t a, std::uint32_t b) {
    const std::uint32_t lo = (a & b) == a ? a : b;
    return lo | ((a ^ b) << 3);
}

/// A triangle on three edges, facing away from `inward`. Its facing is decided on the edges'
/// midpoints: the triangle through points anywhere inside those edges faces the same way (its
/// corners stay on distinct edges, so it never degenerates or flips).
std::uint32_t triangle(glm::uvec2 e0, glm::uvec2 e1, glm::uvec2 e2, glm::vec3 inward) {
    const glm::vec3 m0 = 0.5f * (corner(e0.x) + corner(e0.y));
    const glm::vec3 m1 = 0.5f * (corner(e1.x) + corner(e1.y));
    const glm::vec3 m2 = 0.5f * (corner(e2.x) + corner(e2.y));
    if (glm::dot(glm::cross(m1 - m0, m2 - m0), inward) > 0.0f)
        std::swap(e1, e2); // facing into the fluid: turn it round
    return edgeCode(e0.x, e0.y) | (edgeCode(e1.x, e1.y) << 6) | (edgeCode(e2.x, e2.y) << 12) |
           (1u << 31);
}

CellTriangleTable build() {
    CellTriangleTable table{};
    for (std::uint32_t mask = 0; mask < 256; ++mask) {
        std::size_t k = mask * kCellTrianglesMax;
        for (const auto& tet : kTets) {
            std::uint32_t in[4], out[4], nIn = 0, nOut = 0;
            glm::vec3 sumIn(0.0f), sumOut(0.0f);
            for (std::uint32_t c : tet) {
                if ((mask >> c) & 1u) {
                    in[nIn++] = c;
                    sumIn += corner(c);
                } else {
                    out[nOut++] = c;
                    sumOut += corner(c);
                }
            }
            if (nIn == 0 || nOut == 0)
                continue;
            const glm::vec3 inward = sumIn / float(nIn) - sumOut / float(nOut);
            if (nIn == 1) {
                table[k++] = triangle({in[0], out[0]}, {in[0], out[1]}, {in[0], out[2]}, inward);
            } else if (nIn == 3) {
                table[k++] = triangle({out[0], in[0]}, {out[0], in[1]}, {out[0], in[2]}, inward);
            } else { // a quadrilateral around the tetrahedron: two triangles
                const glm::uvec2 q0{in[0], out[0]}, q1{in[0], out[1]}, q2{in[1], out[1]},
                    q3{in[1], out[0]};
                table[k++] = triangle(q0, q1, q2, inward);
                table[k++] = triangle(q0, q2, q3, inward);
            }
        }
    }
    return table;
}

} // namespace

const CellTriangleTable& cellTriangleTable() {
    static const CellTriangleTable table = build();
    return table;
}

} // namespace sluice::rt
