// The triangles of a grid cell cut by the surface, for every way its eight corners can lie
// inside or outside (marching cubes): one vertex on each of the cell's edges that the surface
// crosses, joined on each face by the segments that face's corners decide alone, so the two
// cells sharing a face cut it the same way and the mesh is closed and manifold
// (docs/surfaces.md, "Contour").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace sluice::rt {

/// Triangles a cell has at most (the table's largest case; CubeTable.cpp checks it).
inline constexpr std::size_t kCellTrianglesMax = 5;

/// Entry [insideMask * kCellTrianglesMax + k]: the k-th triangle of a cell whose inside corners
/// are `insideMask` (bit c for corner c: bit 0 of c is +x, bit 1 +y, bit 2 +z), 0 past the last;
/// then, at [256 * kCellTrianglesMax + insideMask], the case's triangle count.
/// A triangle is three edges of 6 bits each (bits 0-5, 6-11, 12-17), in counter-clockwise order
/// seen from outside; an edge is its lower corner (bits 0-2) and the axis bit to its upper one
/// (bits 3-5: 1, 2 or 4). Bit 31 marks a triangle.
using CellTriangleTable = std::array<std::uint32_t, 256 * kCellTrianglesMax + 256>;

/// The table, built on first use (CubeTable.cpp).
const CellTriangleTable& cellTriangleTable();

} // namespace sluice::rt
