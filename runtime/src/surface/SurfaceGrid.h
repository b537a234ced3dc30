// The surface's sample grid over the particles and the options' defaults
// (SurfaceReconstructor.cpp runs the passes over it; docs/surfaces.md).
#ifndef SLUICE_RT_SURFACE_SURFACE_GRID_H
#define SLUICE_RT_SURFACE_SURFACE_GRID_H

#include <cstdint>

#include <glm/vec3.hpp>

#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::rt {

/// [blocks] most blocks of 8^3 samples the grid over the particles' bounds may have: its flag
/// and slot arrays are 128 MiB then.
constexpr std::uint64_t kMaxBlocks = std::uint64_t{1} << 24;

/// The sample grid over the particles: origin on the global lattice of the cell size (so the
/// same particles give the same samples wherever the run is), and sizes.
struct SurfaceGrid {
    glm::vec3 origin{0.0f};
    glm::ivec3 samples{0};
    glm::ivec3 blocks{0};
    std::uint64_t blockCount = 0;
};

/// The grid over the particles' box [lo, hi] for the resolved options `o`: every kernel fits
/// with three cells to spare. SizeOverflow past kMaxBlocks, saying to use a larger cell.
Result<SurfaceGrid> gridOver(glm::vec3 lo, glm::vec3 hi, const SurfaceOptions& o);

} // namespace sluice::rt

#endif // SLUICE_RT_SURFACE_SURFACE_GRID_H
