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
/// Fixed-point scale of the per-iteration density-error sums (integer adds are order-free, so
/// the sums, and the early stop they drive, are deterministic).
SLUICE_CONST float kErrorFixedScale = 65536.0;

// Uniform block binding.
SLUICE_CONST uint kBindParams = 0;

// Shader storage bindings. Each pass binds the buffers of its roles; ping-pong buffers swap
// which GL buffer sits behind a role, never their contents.
SLUICE_CONST uint kBindPosIn = 0;      ///< vec4 x (xyz) [m]
SLUICE_CONST uint kBindPosOut = 1;
SLUICE_CONST uint kBindVelIn = 2;      ///< vec4 v (xyz) [m/s], w = density error of the particle
SLUICE_CONST uint kBindVelOut = 3;
SLUICE_CONST uint kBindPredIn = 4;     ///< vec4 x* (xyz) [m]
SLUICE_CONST uint kBindPredOut = 5;
SLUICE_CONST uint kBindLambda = 6;     ///< float lambda_i
SLUICE_CONST uint kBindCellCount = 7;  ///< uint per hash bucket
SLUICE_CONST uint kBindCellStart = 8;  ///< uint per hash bucket (exclusive scan of the counts)
SLUICE_CONST uint kBindHash = 9;       ///< uint bucket of each particle
SLUICE_CONST uint kBindRank = 10;      ///< uint rank of each particle inside its bucket
SLUICE_CONST uint kBindSortedToOld = 11; ///< uint source index of each sorted slot
SLUICE_CONST uint kBindOmega = 12;     ///< vec4 vorticity omega_i [1/s]
SLUICE_CONST uint kBindStats = 13;     ///< PbfStats
SLUICE_CONST uint kBindColliders = 14; ///< GpuCollider[]
SLUICE_CONST uint kBindSdf = 15;       ///< float[] every collider's grid, back to back
SLUICE_CONST uint kBindIdIn = 16;      ///< uint particle id
SLUICE_CONST uint kBindIdOut = 17;
SLUICE_CONST uint kBindPredStart = 18; ///< vec4 x* at the substep start: fixes N(i) for the substep
SLUICE_CONST uint kBindPredOther = 19; ///< vec4 x*: the second ping-pong buffer (velocity pass)
SLUICE_CONST uint kBindSolveArgs = 20; ///< PbfDispatchArgs[maxIterations * chunks]
// Prefix scan.
SLUICE_CONST uint kBindScanData = 0;   ///< uint[] exclusive scan output
SLUICE_CONST uint kBindScanSums = 1;   ///< uint[] one total per block
SLUICE_CONST uint kBindScanInput = 2;  ///< uint[] input of scan_block (may be the output)

/// Everything a pass needs to know, one uniform block (std140 and std430 agree: vec4s only).
struct PbfParams {
    vec4 kernel;    ///< h [m], h^2, poly6 coefficient, spiky gradient coefficient
    vec4 fluid;     ///< V = m / rho0 [m^3], epsilon [1/m^2], lambdaRef [m^2], particle radius [m]
    vec4 scorr;     ///< k, n, 1 / W(delta q), 1 / h (cell size inverse)
    vec4 step;      ///< dt [s], 1 / dt, xsph c, vorticity epsilon [m/s]
    vec4 gravity;   ///< [m/s^2] xyz, targetDensityError in w
    vec4 domainMin; ///< [m] xyz shrunk by the radius, w = 1 when a domain box is set
    vec4 domainMax; ///< [m] xyz shrunk by the radius
    uvec4 counts;   ///< particle count, hash table mask, collider count, minIterations
    uvec4 control;  ///< solve dispatch chunks per iteration, hash table size, deterministic,
                    ///< maxIterations
    vec4 gridOrigin; ///< dense cell grid: its corner [m] xyz (the domain's minimum corner)
    uvec4 gridDims;  ///< dense cell grid: cells per axis xyz, w = 1 when the grid replaces the
                     ///< hash (cell (x, y, z) is bucket x + nx (y + ny z)), 0 for the hash
};

/// One collider on the GPU: its placement at the end of the substep and its grid.
struct GpuCollider {
    mat4 worldToGrid;   ///< world [m] -> collider local [asset units]: (R^T (x - p)) / s
    mat4 rotation;      ///< R (upper 3x3), local gradient -> world normal
    mat4 motion;        ///< T(t) T(t + dt)^-1: where a world point riding the collider came from
    vec4 origin;        ///< grid origin (local) xyz, voxel size in w
    vec4 boxMax;        ///< grid far corner origin + (dims - 1) * voxel (local) xyz, scale in w
    uvec4 dims;         ///< grid points per axis xyz, offset of the first value in the SDF buffer
    vec4 material;      ///< friction [0, 1], unused yzw
};

/// Per-iteration density-error accumulators of the current substep.
struct PbfIterationStats {
    uint errorLo;       ///< sum of C_i * kErrorFixedScale, low 32 bits
    uint errorHi;       ///< high 32 bits
    uint errorMaxBits;  ///< floatBitsToUint(max C_i) (C_i >= 0, so uint order is float order)
    uint particles;     ///< particles that contributed
};

/// Indirect group counts of one solver dispatch (glDispatchComputeIndirect). The CPU writes
/// maxIterations x chunks of them at each substep start; the early stop zeroes those of the
/// later iterations, so the idle lambda and delta dispatches launch no work group.
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
    // Followed in the buffer by PbfIterationStats iterations[maxIterations].
};

SLUICE_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(sluice::shared::PbfParams) == 11 * 16, "PbfParams is vec4s only");
static_assert(sizeof(sluice::shared::GpuCollider) == 3 * 64 + 4 * 16, "GpuCollider layout");
static_assert(sizeof(sluice::shared::PbfIterationStats) == 16, "PbfIterationStats layout");
static_assert(sizeof(sluice::shared::PbfStats) == 16, "PbfStats layout");
static_assert(sizeof(sluice::shared::PbfDispatchArgs) == 12, "PbfDispatchArgs layout");
#endif

#endif // SLUICE_SHARED_PBF_H
