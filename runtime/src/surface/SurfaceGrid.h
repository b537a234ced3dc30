// The surface's sample grid over the particles and the options' defaults
// (SurfaceReconstructor.cpp runs the passes over it; docs/surfaces.md).
#ifndef SLUICE_RT_SURFACE_SURFACE_GRID_H
#define SLUICE_RT_SURFACE_SURFACE_GRID_H

#include <array>
#include <cstdint>
#include <optional>

#include <glm/vec3.hpp>

#include "shared/Surface.h"
#include "sluice/gpu/Program.h"
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

/// A particle's rest volume [m^3]: the cube of its spacing, twice the radius.
inline float particleVolume(const SurfaceOptions& o) {
    return 8.0f * o.particleRadius * o.particleRadius * o.particleRadius;
}

/// Sets the grid's uniforms of the surface passes (glsl/SurfaceGlsl.h) on `program`: origin,
/// cell, samples, blocks, support, particle volume, iso (fixed point) and the kernels' kind.
void setGridUniforms(const gpu::Program& program, const SurfaceGrid& g, const SurfaceOptions& o);

/// The Gaussian field's blur along one axis (surface_blur.comp): taps -radius .. radius,
/// weights[k] for taps k and -k, all 2 radius + 1 summing to 1.
struct SurfaceBlur {
    int radius = 0;
    std::array<float, shared::kSurfaceBlurRadiusMax + 1> weights{};
};

/// The blur that, after the trilinear deposit, gives a Gaussian field as wide as poly6 of the
/// support h (per axis, poly6's variance h^2 / 11 = the blur's + the deposit's c^2 / 6), for
/// the resolved options `o`; nullopt where the field is poly6 (anisotropic kernels,
/// SurfaceFieldKernel::Poly6, or a cell outside about h / 8.9 .. h / 2.1, where the blur would
/// need more than kSurfaceBlurRadiusMax taps or less than half a cell of width).
std::optional<SurfaceBlur> gaussianBlur(const SurfaceOptions& o);

} // namespace sluice::rt

#endif // SLUICE_RT_SURFACE_SURFACE_GRID_H
