// How far from a collider's surface sluice-play reads its distance field at a particle
// spacing, and so the band of exact distances a sparse collider needs: sluice-play refuses a
// narrower one, `sluice-bake bake --sparse --for-spacing` bakes the band, `info` says what a
// band serves. One definition for the runtime and the baker, which do not link each other.
#pragma once

#include <cmath>

namespace sluice::format {

/// Bodies' fluid-facing surface lies this many particle spacings inside phi = 0, calibrated on
/// floating cubes (docs/bodies.md, "Surface offset"; the tuned-constants table).
inline constexpr double kBodySurfaceOffsetSpacings = 0.05;

/// The kernel radius h a scene gets unless it sets one, in particle spacings.
inline constexpr double kDefaultKernelSpacings = 2.0;

/// Farthest distance from the surface [m] at which the solver reads a collider's phi: the
/// collision pass reads up to the particle radius (spacing / 2); a dynamic body's boundary
/// volume up to the kernel radius h plus the surface offset.
inline double colliderReach(double spacing, double kernelRadius, bool dynamic) {
    return dynamic ? kernelRadius + kBodySurfaceOffsetSpacings * spacing : 0.5 * spacing;
}

/// Band half-width [voxels] that keeps every distance read within `reach` [m] exact, with
/// voxels of `voxel` [m]: a trilinear cell reaches sqrt(3) voxels beyond the point read.
inline double requiredBandVoxels(double reach, double voxel) {
    return reach / voxel + std::sqrt(3.0);
}

/// How far from the surface [m] a band of `band` voxels of `voxel` [m] keeps trilinear reads
/// exact: the inverse of requiredBandVoxels.
inline double exactReach(double band, double voxel) {
    return std::fmax(band - std::sqrt(3.0), 0.0) * voxel;
}

/// The largest particle spacing [m] a band of `band` voxels of `voxel` [m] serves, for a static
/// collider or a dynamic body, with the default kernel radius; 0 when it serves none.
inline double largestSpacingForBand(double band, double voxel, bool dynamic) {
    const double reach = exactReach(band, voxel);
    return dynamic ? reach / (kDefaultKernelSpacings + kBodySurfaceOffsetSpacings) : 2.0 * reach;
}

} // namespace sluice::format
