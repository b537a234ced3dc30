// The triangles of a grid cell cut by the surface, for every way its eight corners can lie
// inside or outside: the cell split into the six Kuhn tetrahedra that share its main diagonal
// (corner 0 to corner 7), each cut by linear interpolation (one triangle for one or three
// corners inside, two for two), oriented to face out of the fluid. Tetrahedra of neighbouring
// cells meet face to face, so the mesh is closed and manifold (docs/surfaces.md).
#pragma once

#include <array>
#include <cstdint>

namespace sluice::rt {

/// Triangles a cell has at most: two in each of its six tetrahedra.
inline constexpr std::size_t kCellTrianglesMax = 12;

/// Entry [insideMask * kCellTrianglesMax + k]: the k-th triangle of a cell whose inside corners
/// are `insideMask` (bit c for corner c: bit 0 of c is +x, bit 1 +y, bit 2 +z), 0 past the last.
/// A triangle is three edges of 6 bits each (bits 0-5, 6-11, 12-17), in counter-clockwise order
/// seen from outside; an edge is its lower corner (bits 0-2) and the corner offset to its upper
/// one (bits 3-5, 1 to 7: the upper corner is lower | offset). Bit 31 marks a triangle.
using CellTriangleTable = std::array<std::uint32_t, 256 * kCellTrianglesMax>;
const CellTriangleTable& cellTriangleTable();

} // namespace sluice::rt
