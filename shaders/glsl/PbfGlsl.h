// GLSL helpers of the PBF passes: the parameter block, kernels, the cell grid, the candidate
// ranges, the neighbour-mask loop and collider sampling (docs/pbf.md). GLSL only.
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

#ifdef PBF_WITH_COLLIDERS
// Every pass reads the records from the uniform block (shared/Pbf.h, kBindCollidersUniform);
// the body pass writes the dynamic colliders' placement through the storage view of the same
// buffer, and reads only what it does not write in the pass (the grids, and the static
// colliders' placement).
layout(std140, binding = kBindCollidersUniform) uniform CollidersBlock {
    GpuCollider colliders[kMaxColliders];
};
#ifdef PBF_COLLIDERS_WRITABLE
layout(std430, binding = kBindColliders) writeonly buffer CollidersOut {
    GpuCollider colliderRecords[];
};
#endif

#ifdef PBF_WITH_BODIES
// Whether x is so far from the bounding sphere of collider c's body (its farthest contact point
// plus a voxel; a thin feature between contact points may stick out by less than a spacing, so h
// more) that no part of the body is within `reach` of it. The sphere is the collider record's,
// which the body pass writes with the body's pose.
bool bodyOutOfReach(uint c, vec3 x, float reach) {
    vec3 toCentre = x - colliders[c].boundCentre;
    float r = colliders[c].boundRadius + PBF_H + reach;
    return dot(toCentre, toCentre) >= r * r;
}
#endif
// One block for dense and sparse grids alike (a driver may allow as few as 8 per shader).
layout(std430, binding = kBindSdf) readonly buffer SdfBuf { uint sdfWords[]; };
#define pnanovdb_buf_data sdfWords
#include "glsl/NanoVdbGlsl.h"

// The dense grids' samples and the volume maps are fetched through the SDF buffer's texel view:
// on llvmpipe a storage read at an index that differs between lanes is a loop over the lanes
// with a bounds test, a texel fetch one gather, and on a GPU it goes through the texture cache.
// Where the buffer holds more texels than the GL allows, the program is built with
// SLUICE_SDF_STORAGE and reads the storage block (Simulation::Impl::colliderDefines).
#ifndef SLUICE_SDF_STORAGE
layout(binding = kUnitSdfTexels) uniform samplerBuffer sdfTexels;
#endif

float sdfAt(uint base, uvec3 dims, uvec3 p) {
    uint i = base + p.x + dims.x * (p.y + dims.y * p.z);
#ifdef SLUICE_SDF_STORAGE
    // The fetch's bits (a texture path that flushed denormals would differ there; a distance or
    // a share that small is 0 to the solver either way).
    return uintBitsToFloat(sdfWords[i]);
#else
    return texelFetch(sdfTexels, int(i)).x;
#endif
}

// The eight values of a dense grid's cell with lower corner b, as v[x + 2y + 4z]: a collider's
// samples, or its volume map's (BoundaryVolumeGlsl.h).
void denseCorners(uint base, uvec3 dims, uvec3 b, out float v[8]) {
    for (int k = 0; k < 8; ++k)
        v[k] = sdfAt(base, dims, b + uvec3(k & 1, (k >> 1) & 1, k >> 2));
}

// The eight samples of collider c's cell with lower corner b, as v[x + 2y + 4z]: from the dense
// grid, or through a NanoVDB read accessor for a sparse one (glsl/NanoVdbGlsl.h).
void colliderCorners(uint c, uvec3 b, out float v[8]) {
#ifdef SLUICE_SPARSE_COLLIDERS
    if (colliders[c].gridKind == kColliderSparse) {
        pnanovdb_readaccessor_t acc = sparseAccessor(colliders[c].sdfOffset);
        sparseCorners(acc, ivec3(b), v);
        return;
    }
#endif
    denseCorners(colliders[c].sdfOffset, colliders[c].dims, b, v);
}

// Trilinear interpolation in a cell with corners v[x + 2y + 4z] at t in [0, 1]^3, and its
// gradient per cell width.
float trilinearCell(float v[8], vec3 t, out vec3 grad) {
    float v000 = v[0], v100 = v[1], v010 = v[2], v110 = v[3];
    float v001 = v[4], v101 = v[5], v011 = v[6], v111 = v[7];
    float c00 = mix(v000, v100, t.x), c10 = mix(v010, v110, t.x);
    float c01 = mix(v001, v101, t.x), c11 = mix(v011, v111, t.x);
    vec3 w0 = vec3(1.0) - t;
    grad.x = w0.y * w0.z * (v100 - v000) + t.y * w0.z * (v110 - v010) +
             w0.y * t.z * (v101 - v001) + t.y * t.z * (v111 - v011);
    grad.y = w0.x * w0.z * (v010 - v000) + t.x * w0.z * (v110 - v100) +
             w0.x * t.z * (v011 - v001) + t.x * t.z * (v111 - v101);
    grad.z = w0.x * w0.y * (v001 - v000) + t.x * w0.y * (v101 - v100) +
             w0.x * t.y * (v011 - v010) + t.x * t.y * (v111 - v110);
    return mix(mix(c00, c10, t.y), mix(c01, c11, t.y), t.z);
}

// phi and its gradient in collider c's local frame, exactly format::SdfSampler's rule:
// trilinear inside the grid box, phi(clamp(q)) + |q - clamp(q)| outside. A sparse collider
// reads the same way, its samples outside the band being its tiles' (+-band, signed), where the
// gradient is 0.
void sampleCollider(uint c, vec3 q, out float phi, out vec3 grad) {
    vec3 lo = colliders[c].origin;
    float voxel = colliders[c].voxelSize;
    uvec3 dims = colliders[c].dims;
    vec3 qc = clamp(q, lo, colliders[c].boxMax);
    vec3 g = (qc - lo) / voxel;
    vec3 cellLo = clamp(floor(g), vec3(0.0), vec3(dims) - 2.0);
    vec3 t = clamp(g - cellLo, 0.0, 1.0);
    float v[8];
    colliderCorners(c, uvec3(cellLo), v);
    vec3 out_ = q - qc;
    float outside = length(out_);
    phi = trilinearCell(v, t, grad) + outside;
    grad /= voxel;
    if (outside > 0.0) {
        // Outside the box the clamped axes lose their derivative; |q - c| adds its own.
        grad = mix(grad, vec3(0.0), notEqual(out_, vec3(0.0))) + out_ / outside;
    }
}

// The boundary's share of a particle's kernel support (docs/bodies.md, "Boundary volume"): a
// body whose surface is a plane at distance phi from the particle fills the part of the poly6
// support behind that plane, B(phi) = k (1/2 - 315/256 F(phi / h)) with
// F(u) = u - 4u^3/3 + 6u^5/5 - 4u^7/7 + u^9/9, which adds B to V sum_j W (the density over rho0).
// Locally flat boundary, as Koschier & Bender 2017 volume maps assume within h; k calibrates the
// continuous share to the rest lattice's at phi = s/2 (P.boundaryScale).
float boundaryShare(float phi) {
    float u = clamp(phi / PBF_H, -1.0, 1.0);
    float u2 = u * u;
    float f = u * (1.0 + u2 * (-4.0 / 3.0 + u2 * (6.0 / 5.0 + u2 * (-4.0 / 7.0 + u2 / 9.0))));
    return P.boundaryScale * (0.5 - (315.0 / 256.0) * f);
}

// dB/dphi [1/m]: B's gradient is this times the boundary's outward normal.
float boundaryShareSlope(float phi) {
    float u = phi / PBF_H;
    if (abs(u) >= 1.0)
        return 0.0;
    float a = 1.0 - u * u;
    return -P.boundaryScale * (315.0 / 256.0) / PBF_H * (a * a) * (a * a);
}

// World point x in collider c's local frame [asset units].
vec3 colliderLocal(uint c, vec3 x) {
    return (colliders[c].worldToGrid * vec4(x, 1.0)).xyz;
}

// phi in world units and the world normal of collider c at the point whose local position is q.
float colliderDistanceAt(uint c, vec3 q, out vec3 normal) {
    float phiLocal;
    vec3 gradLocal;
    sampleCollider(c, q, phiLocal, gradLocal);
    // R g, as (R^T / s)^T (s g): the rows worldToGrid was read for already (a rotation of its
    // own cost as many reads again on llvmpipe).
    float s = colliders[c].scale;
    normal = transpose(mat3(colliders[c].worldToGrid)) * (s * gradLocal);
    return s * phiLocal;
}

// phi in world units and the world normal of collider c at world point x.
float colliderDistance(uint c, vec3 x, out vec3 normal) {
    return colliderDistanceAt(c, colliderLocal(c, x), normal);
}

// Steps c to the lowest set bit of `bits` (bit c of word c / 32), clearing it; false when none
// is left.
bool nextCollider(inout uvec2 bits, out uint c) {
    uint w = bits.x != 0u ? 0u : 1u;
    c = 32u * w + uint(findLSB(bits[w]));
    bool found = bits[w] != 0u;
    bits[w] &= bits[w] - 1u;
    return found;
}

// docs/pbf.md "Collision": push out to the particle radius along the SDF normal, then remove
// `friction` of the tangential slip relative to the collider. xOld is x at the substep start;
// `near` the colliders to visit in order (collidersNearNow, or allColliders()): the others are
// bodies out of reach.
vec3 collide(vec3 x, vec3 xOld, uvec2 near) {
    uint c;
    while (nextCollider(near, c)) {
#ifdef PBF_WITH_BODIES
        // A body out of reach cannot push: skip its SDF samples. Its phi would be over the
        // radius, so nothing changes.
        if (colliders[c].body != kNoBody && bodyOutOfReach(c, x, PBF_RADIUS))
            continue;
#endif
        vec3 normal;
        float phi = colliderDistance(c, x, normal);
        if (colliders[c].body != kNoBody)
            phi += P.bodyOffset; // docs/bodies.md, "Surface offset"
        float len = length(normal);
#ifdef SLUICE_SPARSE_COLLIDERS
        // Deep inside a sparse collider (an inside tile: phi = -band, no gradient) nothing
        // says which way is out: the particle goes back to where its substep started.
        if (phi < 0.0 && !(len > 0.0)) {
            x = xOld;
            continue;
        }
#endif
        if (!(phi < PBF_RADIUS) || !(len > 0.0))
            continue;
        normal /= len;
        vec3 before = x;
        x += (PBF_RADIUS - phi) * normal;
        vec3 carried = x - (colliders[c].motion * vec4(x, 1.0)).xyz;
        vec3 slip = (x - xOld) - carried;
        vec3 tangential = slip - dot(slip, normal) * normal;
        x -= colliders[c].friction * tangential;
#ifdef PBF_BODY_REACTION
        // A dynamic body takes the opposite of the push it gave (docs/bodies.md).
        if (colliders[c].body != kNoBody)
            PBF_BODY_REACTION(colliders[c].body, x, x - before);
#endif
#ifdef PBF_SOLID_REACTION
        // A collider that is no body has its push summed when its force is measured.
        if (colliders[c].body == kNoBody && colliders[c].forceSlot != kNoBody)
            PBF_SOLID_REACTION(c, x, x - before);
#endif
    }
    return x;
}

// Steps c to the next static or kinematic collider (no body): first the set bits of `mask`
// (P.staticColliders, or a subset of it), then each collider past the 32nd that is no body.
// Start with c = 0; false when there is none left. A loop over all colliders that skipped the
// bodies with `continue` cost about as much as sampling them: llvmpipe runs a skipped trip's SDF
// sample anyway, its lanes masked off (the body pass with 64 crates took 136-185 ms that way
// and 47-51 ms this way: docs/bodies.md, "Sealed contacts"). This takes one trip per static
// collider and none per body.
bool nextStaticCollider(inout uint mask, inout uint c) {
    if (mask != 0u) {
        c = uint(findLSB(mask));
        mask &= mask - 1u;
        return true;
    }
    c = max(c + 1u, 32u);
    while (c < P.colliderCount && colliders[c].body != kNoBody)
        ++c;
    return c < P.colliderCount;
}

#endif // PBF_WITH_COLLIDERS

#ifdef PBF_WITH_BODIES

// Distance and outward unit normal of collider c's body at world x, when the particle's kernel
// reaches it (phi < h); false otherwise. A bounding-sphere test first skips far bodies, and then
// phi is kPhiNotSampled. phi is measured from the body's fluid-facing surface, P.bodyOffset
// inside its zero level set.
const float kPhiNotSampled = 3.0e38;
bool bodyBoundary(uint c, vec3 x, out float phi, out vec3 normal) {
    vec3 toCentre = x - colliders[c].boundCentre;
    float reach = colliders[c].boundRadius + PBF_H;
    phi = kPhiNotSampled;
    normal = vec3(0.0);
    if (dot(toCentre, toCentre) >= reach * reach)
        return false;
    phi = colliderDistance(c, x, normal) + P.bodyOffset;
    float len = length(normal);
    if (!(phi < PBF_H) || !(len > 0.0))
        return false;
    normal /= len;
    return true;
}

// How far world point x lies from the nearest domain wall's face (r beyond the box the centres
// are kept in) or static collider's surface, when nearer than `limit` (else `limit`), and that
// solid's unit normal out of it. The body pass and the sealed contacts' rim (docs/bodies.md,
// "Sealed contacts") use it.
float nearestSolidWithin(vec3 x, float limit, out vec3 normal) {
    float gap = limit;
    normal = vec3(0.0);
    if (P.hasDomain != 0u) {
        vec3 below = x - P.domainMin + PBF_RADIUS, above = P.domainMax - x + PBF_RADIUS;
        for (int a = 0; a < 3; ++a) {
            if (below[a] < gap) {
                gap = below[a];
                normal = vec3(0.0);
                normal[a] = 1.0;
            }
            if (above[a] < gap) {
                gap = above[a];
                normal = vec3(0.0);
                normal[a] = -1.0;
            }
        }
    }
    uint mask = P.staticColliders, c = 0u;
    while (nextStaticCollider(mask, c)) {
        vec3 n;
        float phi = colliderDistance(c, x, n);
        float len = length(n);
        if (phi < gap && len > 0.0) {
            gap = phi;
            normal = n / len;
        }
    }
    return gap;
}
#endif // PBF_WITH_BODIES

vec3 clampToDomain(vec3 x) {
    return P.hasDomain != 0u ? clamp(x, P.domainMin, P.domainMax) : x;
}

#endif // !__cplusplus

#endif // SLUICE_SHARED_PBF_GLSL_H
