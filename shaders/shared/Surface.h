// Fluid surface reconstruction shared by C++ and GLSL (runtime/src/surface/): the sparse
// sample grid's block size, the fixed-point field, the storage bindings and the vertex layout.
// docs/surfaces.md has the algorithm.
#ifndef SLUICE_SHARED_SURFACE_H
#define SLUICE_SHARED_SURFACE_H

#include "shared/GlslBridge.h"

SLUICE_SHARED_BEGIN

/// Samples along each side of a block: the grid is stored only in blocks that particles reach.
SLUICE_CONST uint kSurfaceBlockSide = 8;
/// Samples per block.
SLUICE_CONST uint kSurfaceBlockSamples = kSurfaceBlockSide * kSurfaceBlockSide * kSurfaceBlockSide;
/// Invocations per work group of the per-block passes (one block a group): one per row of
/// kSurfaceBlockSide samples along x. Software GL runs a work group's barriers as switches
/// between all its invocations, so few invocations with a row each beat one per sample.
SLUICE_CONST uint kSurfaceBlockRows = kSurfaceBlockSide * kSurfaceBlockSide;
/// Invocations per work group of the per-particle and per-block-flag passes.
SLUICE_CONST uint kSurfaceLocalSize = 128;
/// Fixed-point scale of the field: each particle adds round(V W * scale) with an integer atomic,
/// so the sums are the same in any order (deterministic) and hold up to 4096 times the bulk.
SLUICE_CONST float kSurfaceFixedScale = 1048576.0;

// Shader storage bindings.
SLUICE_CONST uint kSurfBindPoints = 0;      ///< vec4 particle positions (xyz) [m]
SLUICE_CONST uint kSurfBindBlockFlag = 1;   ///< uint per block of the grid: 1 where stored
SLUICE_CONST uint kSurfBindBlockSlot = 2;   ///< uint per block: exclusive scan of the flags
SLUICE_CONST uint kSurfBindActive = 3;      ///< uint per stored block: its block index
SLUICE_CONST uint kSurfBindField = 4;       ///< uint per stored sample: fixed-point field
SLUICE_CONST uint kSurfBindBlockVerts = 5;  ///< uint per stored block: vertices it owns
SLUICE_CONST uint kSurfBindBlockTris = 6;   ///< uint per stored block: triangles of its cells
SLUICE_CONST uint kSurfBindVertBase = 7;    ///< uint per stored block: first vertex (scanned)
SLUICE_CONST uint kSurfBindTriBase = 8;     ///< uint per stored block: first triangle (scanned)
SLUICE_CONST uint kSurfBindSampleVert = 9;  ///< uint per stored sample: its first vertex
SLUICE_CONST uint kSurfBindSampleCode = 10; ///< uint per stored sample: its crossing edges
                                            ///< (bits 0, 1, 3: +x, +y, +z, bit d - 1 for the
                                            ///< corner offset d) and its cell's corners (8-15)
SLUICE_CONST uint kSurfBindPositions = 11;  ///< float x3 per vertex: its position [m]
SLUICE_CONST uint kSurfBindTriangles = 12;  ///< uint x3 per triangle
SLUICE_CONST uint kSurfBindTriangleTable = 13; ///< uint x5 per cell case, then counts (CubeTable.h)
SLUICE_CONST uint kSurfBindBounds = 14;        ///< SurfaceBounds (surface_bounds.comp)
SLUICE_CONST uint kSurfBindNormals = 15; ///< float x3 per vertex: its unit outward normal
// Anisotropic kernels only (surface_bin_*.comp, surface_anisotropy.comp):
SLUICE_CONST uint kSurfBindBinCount = 16;     ///< uint per block of the grid: its particles
SLUICE_CONST uint kSurfBindBinStart = 17;     ///< uint per block: exclusive scan of the counts
SLUICE_CONST uint kSurfBindBinParticles = 18; ///< uint per particle: indices, block by block
SLUICE_CONST uint kSurfBindKernels = 19;      ///< vec4 x4 per particle: SurfaceKernel's layout
SLUICE_CONST uint kSurfBindBinPoints = 20;    ///< vec4 per particle: positions [m], by block
// The Gaussian field only (surface_deposit.comp, surface_blur.comp):
SLUICE_CONST uint kSurfBindBlurIn = 21;  ///< uint per stored sample: what a blur pass reads
SLUICE_CONST uint kSurfBindBlurOut = 22; ///< uint per stored sample: what it writes
/// Fixed-point scale of the deposit (surface_deposit.comp): a particle's trilinear weights, which
/// sum to 1, add up to this much, so a sample holds up to 4096 particles' whole weight.
SLUICE_CONST float kSurfaceDepositScale = 1048576.0;
/// The blur's reach along each axis, in cells, at most: taps -R .. R, R <= this.
SLUICE_CONST uint kSurfaceBlurRadiusMax = 8;
// The density-normalised field only (surface_density.comp):
SLUICE_CONST uint kSurfBindWeights = 23; ///< float per particle: rest density over its own
/// The least density, as a share of the rest density, a particle's weight is taken from (a
/// lone particle's own is about 0.2): bounds the weight of a particle the field missed.
SLUICE_CONST float kSurfaceDensityFloor = 0.05;
/// Anisotropic kernels (Yu & Turk 2013): the largest ratio of a kernel's longest axis to its
/// shortest (their k_r). With the sphere's volume, no axis is longer than cbrt(ratio^2)
/// supports (a line of particles).
SLUICE_CONST float kSurfaceAnisotropyRatio = 4.0;
/// Particles with fewer neighbours within the support (themselves included) keep the sphere.
SLUICE_CONST uint kSurfaceAnisotropyMinNeighbours = 8;
/// Triangles a cell has at most (marching cubes, CubeTable.h).
SLUICE_CONST uint kSurfaceCellTrianglesMax = 5;


/// The particles' box and non-finite ones (surface_bounds.comp). lo and hi hold floats as
/// order-preserving bits: sign set -> all bits flipped, else the sign bit set.
struct SurfaceBounds {
    uint lo[3];            ///< starts at 0xffffffff
    uint hi[3];            ///< starts at 0
    uint nonFinite;        ///< particles with a NaN or infinite coordinate
    uint firstNonFinite;   ///< the lowest index among them, 0xffffffff when none
};

SLUICE_SHARED_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(sluice::shared::SurfaceBounds) == 32);
#endif

#endif // SLUICE_SHARED_SURFACE_H
