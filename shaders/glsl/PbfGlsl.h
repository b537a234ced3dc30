// GLSL helpers of the PBF passes: the parameter block, kernels, the cell grid, the candidate
// ranges and the neighbour-mask loop (docs/pbf.md); with PBF_WITH_COLLIDERS the colliders'
// (glsl/CollidersGlsl.h). GLSL only.
#ifndef SLUICE_SHARED_PBF_GLSL_H
#define SLUICE_SHARED_PBF_GLSL_H

#include "shared/Pbf.h"
#include "shared/Bodies.h"
#include "shared/ChunkedDispatch.h"

#ifndef __cplusplus

layout(std140, binding = kBindParams) uniform PbfParamsBlock { PbfParams P; };

// Invocations per particle in the neighbour passes (lambda, delta, vorticity, confinement): a
// particle's candidates are split over PBF_LANES adjacent invocations by neighbour-mask word
// (word w goes to lane w % PBF_LANES), and their sums are added in a fixed tree (pbfLaneSum).
// On a GPU a small scene then fills more of the machine and each invocation walks a fraction of
// the neighbours; 1 (every particle one invocation) on software renderers and large scenes.
#ifndef PBF_LANES
#define PBF_LANES 1
#endif
const uint kPbfLanes = uint(PBF_LANES);
// This invocation's lane; set by the pass's main before any neighbour loop.
uint pbfLane = 0u;
// In a loop over mask words: skips word w unless it is this lane's (nothing with one lane).
#if PBF_LANES > 1
#define PBF_SKIP_OTHER_LANES(w)                                                                \
    if ((w) % kPbfLanes != pbfLane)                                                            \
        continue;
#else
#define PBF_SKIP_OTHER_LANES(w)
#endif

#define PBF_H (P.h)
#define PBF_H2 (P.h2)
#define PBF_VOLUME (P.volume)
#define PBF_RADIUS (P.radius)
#define PBF_DT (P.dt)
#define PBF_COUNT (P.particleCount)

// Mueller et al. 2003: poly6 W(q) from q^2, and the spiky gradient of x (both 0 outside h).
float poly6(float q2) {
    float a = PBF_H2 - q2;
    return q2 < PBF_H2 ? P.poly6Coeff * a * a * a : 0.0;
}
vec3 spikyGrad(vec3 x, float q2) {
    if (q2 >= PBF_H2 || q2 <= 0.0)
        return vec3(0.0);
    float q = sqrt(q2);
    float a = PBF_H - q;
    return (P.spikyGradCoeff * a * a / q) * x;
}

// The cells are h wide. With a domain box (P.denseGrid = 1) they form a dense grid from the
// domain's corner, and a position outside it counts in the nearest boundary cell (clamping
// keeps cells of points closer than h at most one apart, so no neighbour is lost); otherwise
// they are unbounded and hashed into the table of P.hashMask + 1 buckets.
bool denseGrid() { return P.denseGrid != 0u; }

ivec3 cellOf(vec3 x) {
    return pbfCellOf(x, P.gridOrigin, denseGrid() ? P.gridDims : uvec3(0u), P.invH);
}

uint cellHash(ivec3 c) {
    return pbfCellHash(c, P.hashMask);
}

// The bucket of cell c: its dense index, or its hash.
uint cellBucket(ivec3 c) {
    return denseGrid() ? pbfDenseBucket(c, P.gridDims) : cellHash(c);
}

// Finite test on the bits: compilers may assume isnan() and isinf() are false.
bool allFinite(vec3 v) {
    uvec3 exponent = floatBitsToUint(v) & uvec3(0x7f800000u);
    return all(notEqual(exponent, uvec3(0x7f800000u)));
}

#include "glsl/NeighbourReadsGlsl.h"

// The candidate ranges of particle i: the sorted particles a neighbour search from i's start
// cell visits (docs/pbf.md step 3). START[] (x* at the substep start, sorted) chooses the cell.
// On the dense grid the three cells x - 1 .. x + 1 of a row are adjacent buckets, so their
// particles are one contiguous range: 9 ranges. On the hash, the 27 buckets; a candidate whose
// own start cell is not the visited cell came through a hash collision. Inside: cc_ the cell
// visited (on the dense grid the row's x - 1 cell; only the hash tests it), begin_ .. end_ the
// range, pbfBase_ the candidate number of begin_ (candidates are numbered 0, 1, ... in this
// visiting order). Close with PBF_RANGES_END, which advances pbfBase_ (in scope after it: the
// candidate count).
#define PBF_RANGES_BEGIN(START, i)                                                             \
        ivec3 pbfCell_ = cellOf(PBF_START_AT(START, i).xyz);                                   \
        bool pbfDense_ = denseGrid();                                                          \
        ivec3 pbfDims_ = ivec3(P.gridDims);                                                    \
        int pbfRanges_ = pbfDense_ ? 1 : 3;                                                    \
        uint pbfBase_ = 0u;                                                                    \
        for (int dz_ = -1; dz_ <= 1; ++dz_)                                                    \
            for (int dy_ = -1; dy_ <= 1; ++dy_)                                                \
                for (int dx_ = 0; dx_ < pbfRanges_; ++dx_) {                                   \
                    ivec3 cc_ = pbfCell_ + ivec3(dx_ - 1, dy_, dz_);                           \
                    uint begin_, end_;                                                         \
                    if (pbfDense_) {                                                           \
                        if (cc_.y < 0 || cc_.y >= pbfDims_.y || cc_.z < 0 || cc_.z >= pbfDims_.z) \
                            continue;                                                          \
                        ivec3 lo_ = ivec3(max(pbfCell_.x - 1, 0), cc_.y, cc_.z);               \
                        ivec3 hi_ = ivec3(min(pbfCell_.x + 1, pbfDims_.x - 1), cc_.y, cc_.z);  \
                        begin_ = PBF_CELL_START_AT(cellBucket(lo_));                           \
                        end_ = PBF_CELL_START_AT(cellBucket(hi_) + 1u);                        \
                    } else {                                                                   \
                        uint bucket_ = cellHash(cc_);                                          \
                        begin_ = PBF_CELL_START_AT(bucket_);                                   \
                        end_ = PBF_CELL_START_AT(bucket_ + 1u);                                \
                    }
#define PBF_RANGES_END                                                                         \
    pbfBase_ += end_ - begin_;                                                                 \
    }

// Whether candidate j, met in cell cc of the visit from i, is in N(i): another particle whose
// start cell is cc (hash collisions excluded) and whose start x* was closer than h.
bool pbfIsNeighbour(vec3 startI, vec3 startJ, uint i, uint j, bool dense, ivec3 cc) {
    if (j == i || (!dense && cellOf(startJ) != cc))
        return false;
    vec3 d = startI - startJ;
    return dot(d, d) < PBF_H2;
}

// Neighbour loop over N(i), from the mask lambda of iteration 0 recorded (pbf_lambda.comp): the
// candidate ranges again (a few reads of cellStart), and in each range the mask words that
// cover it, one read per word, visiting the set bits in order (so the sums run in the order of
// a full search). Candidates past the mask's bits get their word's bits from the full test.
// The shader declares MASK (uint[kNeighbourMaskWords] per particle) and cellStart.
// Inside the body: j, pj = POS[j], xj = pj.xyz, d = xi - xj and q2 = |d|^2 from the current positions
// POS (q2 may reach h as particles move; the kernels are 0 there). The body must not use
// `continue`. Close with PBF_NEIGHBOURS_END.
#define PBF_NEIGHBOURS_BEGIN(START, MASK, POS, i, xi)                                         \
    {                                                                                          \
        vec3 pbfStartI_ = PBF_START_AT(START, i).xyz;                                          \
        uint pbfMaskBase_ = (i) * kNeighbourMaskWords;                                         \
        PBF_RANGES_BEGIN(START, i)                                                             \
        uint pbfStop_ = pbfBase_ + (end_ - begin_);                                            \
        for (uint pbfW_ = pbfBase_ >> 5u; pbfW_ < ((pbfStop_ + 31u) >> 5u); ++pbfW_) {        \
            PBF_SKIP_OTHER_LANES(pbfW_)                                                        \
            uint pbfFirst_ = pbfW_ << 5u; /* candidate number of the word's bit 0 */           \
            uint pbfLo_ = max(pbfBase_, pbfFirst_) - pbfFirst_;                                \
            uint pbfHi_ = min(pbfStop_, pbfFirst_ + 32u) - pbfFirst_;                          \
            uint pbfBits_ = 0u;                                                                \
            if (pbfW_ < kNeighbourMaskWords) {                                                 \
                uint keep_ = pbfHi_ < 32u ? (1u << pbfHi_) - 1u : 0xffffffffu;                 \
                pbfBits_ = PBF_MASK_AT(MASK, pbfMaskBase_ + pbfW_) & keep_ &                  \
                           (0xffffffffu << pbfLo_);                                            \
            } else {                                                                           \
                for (uint b_ = pbfLo_; b_ < pbfHi_; ++b_) {                                    \
                    uint jj_ = begin_ + (pbfFirst_ + b_ - pbfBase_);                           \
                    vec3 xjj_ = PBF_START_AT(START, jj_).xyz;                                  \
                    if (pbfIsNeighbour(pbfStartI_, xjj_, i, jj_, pbfDense_, cc_))              \
                        pbfBits_ |= 1u << b_;                                                  \
                }                                                                              \
            }                                                                                  \
            while (pbfBits_ != 0u) {                                                           \
                uint j = begin_ + (pbfFirst_ + uint(findLSB(pbfBits_)) - pbfBase_);            \
                pbfBits_ &= pbfBits_ - 1u;                                                     \
                vec4 pj = PBF_POS_AT(POS, j);                                                  \
                vec3 xj = pj.xyz;                                                              \
                vec3 d = xi - xj;                                                              \
                float q2 = dot(d, d);
#define PBF_NEIGHBOURS_END                                                                     \
    }                                                                                          \
    }                                                                                          \
    PBF_RANGES_END                                                                             \
    }

#if PBF_LANES > 1
shared vec4 pbfLaneSums[kPbfLocalSize];
#endif

// The sum of v over the PBF_LANES invocations of this invocation's particle, the same in each of
// them: a fixed tree in shared memory, so every run adds in the same order. Every invocation of
// the group must call it (it holds barriers), the same number of times.
vec4 pbfLaneSum(vec4 v) {
#if PBF_LANES > 1
    uint t = gl_LocalInvocationID.x;
    uint lane = t % kPbfLanes;
    barrier(); // the last call's reads are done
    pbfLaneSums[t] = v;
    for (uint s = kPbfLanes / 2u; s > 0u; s >>= 1u) {
        barrier();
        if (lane < s)
            pbfLaneSums[t] += pbfLaneSums[t + s];
    }
    barrier();
    return pbfLaneSums[t - lane];
#else
    return v;
#endif
}

// The particle and lane of this invocation of a neighbour pass (macros: gl_WorkGroupSize may
// only be used after the pass's local_size line).
#define PBF_PARTICLE (SLUICE_GLOBAL_ID.x / kPbfLanes)
#define PBF_LANE (SLUICE_GLOBAL_ID.x % kPbfLanes)

#ifdef PBF_WITH_BODIES
layout(std430, binding = kBindBodies) buffer BodiesBuf { GpuBody bodies[]; };

#endif

// The colliders: their records, sampling their fields, the boundary share and collisions.
#include "glsl/CollidersGlsl.h"

vec3 clampToDomain(vec3 x) {
    return P.hasDomain != 0u ? clamp(x, P.domainMin, P.domainMax) : x;
}

#endif // !__cplusplus

#endif // SLUICE_SHARED_PBF_GLSL_H
