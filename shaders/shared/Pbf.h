// PBF solver data shared by C++ and GLSL: parameter block, collider records, statistics,
// binding indices and work-group sizes (docs/pbf.md is the algorithm).
#ifndef SLUICE_SHARED_PBF_H
#define SLUICE_SHARED_PBF_H

#include "shared/GlslBridge.h"

SLUICE_SHARED_BEGIN

/// Invocations per work group of every per-particle pass.
SLUICE_CONST uint kPbfLocalSize = 128;
/// Elements one work group of the prefix scan handles (two per invocation).
SLUICE_CONST uint kScanBlock = 1024;
/// Blocks whose totals scan_add.comp adds up itself at most (two dispatches for up to
/// kScanBlock * kScanReducedBlocks elements, each work group reading at most 16 totals an
/// invocation); more are scanned by a level of their own.
SLUICE_CONST uint kScanReducedBlocks = 8192;
/// Work groups one dispatch launches at most; more are split into chunks (ChunkedDispatch.h).
SLUICE_CONST uint kPbfMaxGroupsPerDispatch = 65535;
/// PbfStats::stopIteration before any iteration met the target.
SLUICE_CONST uint kPbfNoStop = 0xffffffffu;
/// Fixed-point scale of the per-iteration density-error sums (integer adds are order-free, so
/// the sums, and the early stop they drive, are deterministic).
SLUICE_CONST float kErrorFixedScale = 65536.0;
/// 32-bit words of each particle's neighbour mask: one bit per candidate entry of its cell
/// ranges, in visiting order (docs/pbf.md step 3), written by lambda of iteration 0. Candidates past kNeighbourMaskBits are
/// tested in full by every pass and counted in PbfStats::maskOverflow.
SLUICE_CONST uint kNeighbourMaskWords = 12;
SLUICE_CONST uint kNeighbourMaskBits = kNeighbourMaskWords * 32;

// Uniform block bindings.
SLUICE_CONST uint kBindParams = 0;
/// The collider records as a uniform block of kMaxColliders GpuCollider, for every pass that
/// reads them; the body pass also writes them through kBindColliders (the same buffer). On
/// llvmpipe a storage-buffer read at an index that differs between a vector's lanes is a loop
/// over the lanes for each component, with a bounds test each, where a uniform block's is one
/// gather: the 16-crate step of tests/bench/pbf/bodies.py went from 96 to 89 ms that way
/// (docs/bodies.md, "Collider records in a uniform block").
SLUICE_CONST uint kBindCollidersUniform = 1;
/// Colliders a scene holds at most (format::kMaxSceneColliders): the uniform block's length.
SLUICE_CONST uint kMaxColliders = 64;
/// Drain boxes (and one-shot removal boxes) a substep tests particles against.
SLUICE_CONST uint kMaxDrains = 8;

// Texture unit.
/// The SDF buffer's texel view (samplerBuffer, GL_R32F over kBindSdf's buffer): the dense grids'
/// samples and the volume maps are fetched through it (PbfGlsl.h, sdfAt).
SLUICE_CONST uint kUnitSdfTexels = 0;
/// The neighbour passes' texel views (NeighbourReadsGlsl.h): x* at the substep start
/// (GL_RGBA32F over predStart), the positions the pass reads at its neighbours (x* of the
/// iteration in the solve, x in vorticity and confinement), the velocities and vorticities of
/// vorticity and confinement, the neighbour masks and the cell ranges (GL_R32UI).
SLUICE_CONST uint kUnitStartTexels = 1;
SLUICE_CONST uint kUnitPosTexels = 2;
SLUICE_CONST uint kUnitVelTexels = 3;
SLUICE_CONST uint kUnitOmegaTexels = 4;
SLUICE_CONST uint kUnitMaskTexels = 5;
SLUICE_CONST uint kUnitCellStartTexels = 6;

// Shader storage bindings. Each pass binds the buffers of its roles; ping-pong buffers swap
// which GL buffer sits behind a role, never their contents.
SLUICE_CONST uint kBindPosIn = 0;      ///< vec4 x (xyz) [m]
SLUICE_CONST uint kBindPosOut = 1;
SLUICE_CONST uint kBindVelIn = 2;      ///< vec4 v (xyz) [m/s], w = density error of the particle
SLUICE_CONST uint kBindVelOut = 3;
SLUICE_CONST uint kBindPredIn = 4;     ///< vec4 x* (xyz) [m]
SLUICE_CONST uint kBindPredOut = 5;
// Binding 6 is free: lambda_i lives in the w of the x* it was computed from (pbf_lambda.comp).
SLUICE_CONST uint kBindCellCount = 7;  ///< uint per hash bucket: particles counted into it by the
                                       ///< predict pass; the scan reads and zeroes it
SLUICE_CONST uint kBindCellStart = 8;  ///< uint per hash bucket and one more: the exclusive scan
                                       ///< of the counts, so bucket b is cellStart[b] .. cellStart[b + 1]
SLUICE_CONST uint kBindHash = 9;       ///< uint bucket of each particle
SLUICE_CONST uint kBindRank = 10;      ///< uint rank of each particle inside its bucket
SLUICE_CONST uint kBindSortedToOld = 11; ///< uint source index of each sorted slot
SLUICE_CONST uint kBindOmega = 12;     ///< vec4 vorticity omega_i [1/s]
SLUICE_CONST uint kBindStats = 13;     ///< PbfStats
SLUICE_CONST uint kBindColliders = 14; ///< GpuCollider[kMaxColliders], written by the body pass
SLUICE_CONST uint kBindSdf = 15;       ///< uint[] every collider's samples, back to back: dense
                                       ///< grids as float bits, sparse ones as NanoVDB grids
SLUICE_CONST uint kBindIdIn = 16;      ///< uint particle id
SLUICE_CONST uint kBindIdOut = 17;
SLUICE_CONST uint kBindPredStart = 18; ///< vec4 x* at the substep start: fixes N(i) for the substep
SLUICE_CONST uint kBindRemoveIds = 19; ///< uint[] ids to remove this substep, ascending
SLUICE_CONST uint kBindSolveArgs = 20; ///< PbfDispatchArgs[maxIterations * chunks]
SLUICE_CONST uint kBindNeighbourMask = 21; ///< uint[kNeighbourMaskWords] per sorted particle

// GpuCollider::gridKind: how its samples are stored in the SDF buffer.
SLUICE_CONST uint kColliderDense = 0;  ///< float per grid point, x fastest
SLUICE_CONST uint kColliderSparse = 1; ///< a NanoVDB float grid, at a 32-byte aligned offset
// Volume maps of static colliders (docs/pbf.md, "Volume maps"; pbf_volume_map.comp).
SLUICE_CONST uint kNoVolumeMap = 0xffffffffu; ///< GpuCollider::volumeMap of a collider without one
SLUICE_CONST uint kVolumeMapSteps = 5;        ///< quadrature points per kernel radius, each way
SLUICE_CONST uint kVolumeMapMaxPoints = 1u << 24; ///< a larger grid keeps the flat closed form
SLUICE_CONST uint kBindVolumeMapOut = 27; ///< float[]: the SDF buffer again, written by the map pass
// Prefix scan.
SLUICE_CONST uint kBindScanData = 0;   ///< uint[] exclusive scan output
SLUICE_CONST uint kBindScanSums = 1;   ///< uint[] one total per block
SLUICE_CONST uint kBindScanInput = 2;  ///< uint[] input of scan_block (may be the output)

/// Everything a pass needs to know, one uniform block. std140 and std430 agree on it: scalars
/// and 16-byte aligned vec3s, each vec3 followed by a scalar that fills its row. Offsets [bytes]
/// on the left are checked below.
// clang-format off
struct PbfParams {
    // Kernel.
    /*   0 */ float h;              ///< kernel radius [m]
    /*   4 */ float h2;             ///< h^2 [m^2]
    /*   8 */ float poly6Coeff;     ///< poly6 coefficient 315 / (64 pi h^9) [1/m^9]
    /*  12 */ float spikyGradCoeff; ///< spiky gradient coefficient -45 / (pi h^6) [1/m^6]
    // Fluid.
    /*  16 */ float volume;    ///< particle volume V = m / rho0 [m^3]
    /*  20 */ float epsilon;   ///< lambda relaxation: relaxation * sRest [1/m^2]
    /*  24 */ float lambdaRef; ///< 1 / (sRest + epsilon) [m^2]
    /*  28 */ float radius;    ///< particle radius [m]
    // Tensile instability correction s_corr (Macklin & Mueller 2013, eq. 13).
    /*  32 */ float scorrK;     ///< k
    /*  36 */ float scorrN;     ///< n
    /*  40 */ float invWDeltaQ; ///< 1 / W(delta q) [m^3], 0 when W(delta q) is 0
    /*  44 */ float invH;       ///< 1 / h: inverse cell size of the neighbour grid [1/m]
    // Step.
    /*  48 */ float dt;        ///< substep [s]
    /*  52 */ float invDt;     ///< 1 / dt [1/s]
    /*  56 */ float xsph;      ///< XSPH viscosity c
    /*  60 */ float vorticity; ///< vorticity confinement epsilon [m/s]
    /*  64 */ vec3 gravity;             ///< [m/s^2]
    /*  76 */ float targetDensityError; ///< early stop: mean C_i at or below it; 0 never stops
    // Domain box, shrunk by the particle radius.
    /*  80 */ vec3 domainMin; ///< [m]
    /*  92 */ uint hasDomain; ///< 1 when a domain box is set, 0 otherwise
    /*  96 */ vec3 domainMax; ///< [m]
    /* 108 */ uint pad108;
    // Counts.
    /* 112 */ uint particleCount; ///< particles now live
    /* 116 */ uint hashMask;      ///< hash table size - 1 (the size is a power of two)
    /* 120 */ uint colliderCount; ///< GpuCollider records bound
    /* 124 */ uint minIterations; ///< solver iterations before the early stop may end them
    // Solver control.
    /* 128 */ uint solveChunks;   ///< indirect dispatches per lambda or delta pass
    /* 132 */ uint activeBuckets; ///< buckets in use: dense grid cells, or the hash table size
    /* 136 */ uint deterministic; ///< 1: restore a fixed order inside each bucket after the sort
    /* 140 */ uint maxIterations; ///< solver iterations at most
    // Dense cell grid over the domain box, when it replaces the hash.
    /* 144 */ vec3 gridOrigin; ///< its minimum corner (the domain's) [m]
    /* 156 */ float bodyOffset; ///< bodies' fluid-facing surface lies this far inside phi = 0 [m]
    /* 160 */ uvec3 gridDims;  ///< cells per axis; cell (x, y, z) is bucket x + nx (y + ny z)
    /* 172 */ uint denseGrid;  ///< 1 when the dense grid replaces the hash, 0 for the hash
    // Dynamic bodies (shared/Bodies.h).
    /* 176 */ uint bodyCount;      ///< GpuBody records bound
    /* 180 */ float particleMass;  ///< m [kg]: a correction dx of a particle is m dx / dt of impulse
    /* 184 */ float boundaryScale; ///< calibration of the bodies' boundary volume (docs/bodies.md)
    /* 188 */ uint staticColliders; ///< bit c set: collider c (< 32) is no body (PbfGlsl.h)
    // Removal (docs/embedding.md, "Removing particles"): the predict pass sends a particle in
    // a drain box, or one whose id is listed, to the bucket after the last (activeBuckets), so
    // the sort puts it after the live ones.
    /* 192 */ uint drainCount;    ///< boxes in drainMin / drainMax
    /* 196 */ uint removeIdCount; ///< ids in the kBindRemoveIds buffer
    /* 200 */ uint removal;       ///< 1 when a particle may have been removed: the passes after
                                  ///< the sort read the live count (PBF_LIVE)
    /* 204 */ uint measuredForces; ///< 1 when some collider that is no body has its force
                                   ///< measured (GpuCollider::forceSlot)
    /* 208 */ vec4 drainMin[kMaxDrains]; ///< xyz: a box's minimum corner [m]
    /* 336 */ vec4 drainMax[kMaxDrains]; ///< xyz: its maximum corner [m]
};

/// One collider on the GPU: its placement at the end of the substep and its grid. The same bytes
/// in std430 (the body pass's storage view) and std140 (the uniform block every other pass
/// reads): every member is 16-byte aligned or packs into a vec3's last word.
struct GpuCollider {
    /*   0 */ mat4 worldToGrid; ///< world [m] -> collider local [asset units]: (R^T (x - p)) / s;
                                ///< its upper 3x3 transposed, times s, turns a local gradient
                                ///< into the world one
    /*  64 */ vec3 boundCentre; ///< a body's centre of mass [m], which its bounding sphere is about
    /*  76 */ float boundRadius; ///< that sphere's radius [m] (GpuBody::boundRadius), kept here
                                 ///< beside the grid the passes sample; 0 for no body
    /*  80 */ mat4 motion; ///< T(t) T(t + dt)^-1: where a world point riding the collider came from
    /* 144 */ vec3 origin;      ///< grid origin (local) [asset units]
    /* 156 */ float voxelSize;  ///< grid spacing (local) [asset units]
    /* 160 */ vec3 boxMax;      ///< grid far corner origin + (dims - 1) voxelSize (local)
    /* 172 */ float scale;      ///< uniform scale s of the placement (local -> world)
    /* 176 */ uvec3 dims;       ///< grid points per axis
    /* 188 */ uint sdfOffset;   ///< where its samples start in the SDF buffer: dense, the first
                                ///< value [words]; sparse, the NanoVDB grid [bytes]
    /* 192 */ float friction;   ///< share of the tangential slip removed on contact, [0, 1]
    /* 196 */ uint body;      ///< its GpuBody when the collider is dynamic, else kNoBody
    /* 200 */ uint gridKind;  ///< kColliderDense or kColliderSparse
    /* 204 */ uint volumeMap; ///< where its volume map starts in the SDF buffer [words]: one float
                              ///< per grid point (dense layout) or per voxel of each leaf (sparse,
                              ///< 512 a leaf in the tree's order), or kNoVolumeMap
                              ///< (BoundaryVolumeGlsl.h; docs/pbf.md, "Volume maps")
    /* 208 */ vec3 forcePoint; ///< a collider that is no body: its origin at the substep's end,
                               ///< which its measured torque is about [m]
    /* 220 */ uint forceSlot;  ///< where its pushes are summed in the body sums (shared/Bodies.h)
                               ///< when its force is measured, else kNoBody
};
// clang-format on

/// Per-iteration density-error accumulators of the current substep.
struct PbfIterationStats {
    uint errorLo;       ///< sum of C_i * kErrorFixedScale, low 32 bits
    uint errorHi;       ///< high 32 bits
    uint errorMaxBits;  ///< floatBitsToUint(max C_i) (C_i >= 0, so uint order is float order)
    uint particles;     ///< particles that contributed
};

/// Indirect group counts of one solver dispatch (glDispatchComputeIndirect). The predict pass
/// writes maxIterations x chunks of them at each substep start; the early stop zeroes those of
/// the later iterations, so the idle lambda and delta dispatches launch no work group.
struct PbfDispatchArgs {
    uint groupsX;
    uint groupsY;
    uint groupsZ;
};

/// Counters the passes write with atomics; the CPU reads them once per recorded step.
struct PbfStats {
    uint nonFinite;        ///< particles reset because x* or v went non-finite (this step)
    uint insideColliders;  ///< particles with min phi < -0.5 r (stats pass)
    uint maxSpeedBits;     ///< floatBitsToUint(max |v|) [m/s] (stats pass)
    uint stopIteration;    ///< first iteration whose error met the target, or 0xffffffff
    uint maskOverflow;     ///< particle-substeps whose candidates outnumbered the mask bits (this step)
    uint maxCandidates;    ///< most candidate entries one particle visited (this step)
    uint maxNeighbours;    ///< most neighbours one particle had (this step)
    uint iterationSum;     ///< solver iterations summed over the substeps (this step)
    uint solveDispatches;  ///< lambda and delta dispatches that launched work groups (this step)
    uint bodyFaults;       ///< bodies put back because their state went non-finite or their
                           ///< centre left the domain box (since the start, not reset per step)
    // Followed in the buffer by PbfIterationStats iterations[maxIterations].
};

/// The neighbour grid's cell of a point x [m] (docs/pbf.md step 3): on the dense grid from
/// `origin` with `dims` cells per axis, clamped into it (a point outside counts in the nearest
/// boundary cell, so cells of points closer than h stay at most one apart); unbounded cells
/// (dims.x == 0) otherwise. invH = 1 / h [1/m]. The GPU passes and the tests' decoder of the
/// neighbour mask call this one definition.
SLUICE_FUNC ivec3 pbfCellOf(vec3 x, vec3 origin, uvec3 dims, float invH) {
    if (dims.x == 0u)
        return ivec3(floor(x * invH));
    return clamp(ivec3(floor((x - origin) * invH)), ivec3(0), ivec3(dims) - 1);
}

/// Cell c's bucket in a table of mask + 1 buckets (a power of two), for unbounded cells: the
/// spatial hash of Teschner et al. 2003, in uint arithmetic.
SLUICE_FUNC uint pbfCellHash(ivec3 c, uint mask) {
    return ((uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u)) & mask;
}

/// Cell c's bucket on the dense grid of `dims` cells: x fastest.
SLUICE_FUNC uint pbfDenseBucket(ivec3 c, uvec3 dims) {
    return uint(c.x) + dims.x * (uint(c.y) + dims.y * uint(c.z));
}

SLUICE_SHARED_END

#ifdef __cplusplus
#include <cstddef>
#define SLUICE_PBF_AT(type, field, offset)                                                         \
    static_assert(offsetof(sluice::shared::type, field) == (offset), "offset of " #field)
SLUICE_PBF_AT(PbfParams, h, 0);
SLUICE_PBF_AT(PbfParams, spikyGradCoeff, 12);
SLUICE_PBF_AT(PbfParams, volume, 16);
SLUICE_PBF_AT(PbfParams, radius, 28);
SLUICE_PBF_AT(PbfParams, scorrK, 32);
SLUICE_PBF_AT(PbfParams, invH, 44);
SLUICE_PBF_AT(PbfParams, dt, 48);
SLUICE_PBF_AT(PbfParams, vorticity, 60);
SLUICE_PBF_AT(PbfParams, gravity, 64);
SLUICE_PBF_AT(PbfParams, targetDensityError, 76);
SLUICE_PBF_AT(PbfParams, domainMin, 80);
SLUICE_PBF_AT(PbfParams, hasDomain, 92);
SLUICE_PBF_AT(PbfParams, domainMax, 96);
SLUICE_PBF_AT(PbfParams, particleCount, 112);
SLUICE_PBF_AT(PbfParams, minIterations, 124);
SLUICE_PBF_AT(PbfParams, solveChunks, 128);
SLUICE_PBF_AT(PbfParams, maxIterations, 140);
SLUICE_PBF_AT(PbfParams, gridOrigin, 144);
SLUICE_PBF_AT(PbfParams, bodyOffset, 156);
SLUICE_PBF_AT(PbfParams, gridDims, 160);
SLUICE_PBF_AT(PbfParams, denseGrid, 172);
SLUICE_PBF_AT(PbfParams, bodyCount, 176);
SLUICE_PBF_AT(PbfParams, particleMass, 180);
SLUICE_PBF_AT(PbfParams, boundaryScale, 184);
SLUICE_PBF_AT(PbfParams, staticColliders, 188);
SLUICE_PBF_AT(PbfParams, drainCount, 192);
SLUICE_PBF_AT(PbfParams, removal, 200);
SLUICE_PBF_AT(PbfParams, drainMin, 208);
SLUICE_PBF_AT(PbfParams, drainMax, 336);
static_assert(sizeof(sluice::shared::PbfParams) == 464, "std140/std430 size of PbfParams");
SLUICE_PBF_AT(GpuCollider, worldToGrid, 0);
SLUICE_PBF_AT(GpuCollider, boundCentre, 64);
SLUICE_PBF_AT(GpuCollider, boundRadius, 76);
SLUICE_PBF_AT(GpuCollider, motion, 80);
SLUICE_PBF_AT(GpuCollider, origin, 144);
SLUICE_PBF_AT(GpuCollider, voxelSize, 156);
SLUICE_PBF_AT(GpuCollider, boxMax, 160);
SLUICE_PBF_AT(GpuCollider, scale, 172);
SLUICE_PBF_AT(GpuCollider, dims, 176);
SLUICE_PBF_AT(GpuCollider, sdfOffset, 188);
SLUICE_PBF_AT(GpuCollider, friction, 192);
SLUICE_PBF_AT(GpuCollider, body, 196);
SLUICE_PBF_AT(GpuCollider, gridKind, 200);
SLUICE_PBF_AT(GpuCollider, volumeMap, 204);
SLUICE_PBF_AT(GpuCollider, forcePoint, 208);
SLUICE_PBF_AT(GpuCollider, forceSlot, 220);
static_assert(sizeof(sluice::shared::GpuCollider) == 224, "std430 and std140 size of GpuCollider");
static_assert(sluice::shared::kMaxColliders * sizeof(sluice::shared::GpuCollider) <= 16384,
              "the colliders' uniform block fits the 16 KiB every GL 4.5 driver allows");
SLUICE_PBF_AT(PbfIterationStats, errorHi, 4);
SLUICE_PBF_AT(PbfIterationStats, errorMaxBits, 8);
SLUICE_PBF_AT(PbfIterationStats, particles, 12);
static_assert(sizeof(sluice::shared::PbfIterationStats) == 16, "std430 size of PbfIterationStats");
SLUICE_PBF_AT(PbfStats, insideColliders, 4);
SLUICE_PBF_AT(PbfStats, maxSpeedBits, 8);
SLUICE_PBF_AT(PbfStats, stopIteration, 12);
SLUICE_PBF_AT(PbfStats, maskOverflow, 16);
SLUICE_PBF_AT(PbfStats, maxCandidates, 20);
SLUICE_PBF_AT(PbfStats, maxNeighbours, 24);
SLUICE_PBF_AT(PbfStats, iterationSum, 28);
SLUICE_PBF_AT(PbfStats, solveDispatches, 32);
SLUICE_PBF_AT(PbfStats, bodyFaults, 36);
static_assert(sizeof(sluice::shared::PbfStats) == 40, "std430 size of PbfStats");
static_assert(sizeof(sluice::shared::PbfDispatchArgs) == 12, "std430 size of PbfDispatchArgs");
#undef SLUICE_PBF_AT
#endif

#endif // SLUICE_SHARED_PBF_H
