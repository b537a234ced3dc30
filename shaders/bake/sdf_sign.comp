// Sign passes: the fast winding number (Barill et al. 2018), negating the unsigned distance where
// a point is inside. Three variants:
//   SDF_SIGN_COARSE: one coarse point per invocation (distances in the coarse buffer; with
//       SDF_POINTS, one query point);
//   default: one block of the pending list (sdf_distance.comp) per invocation, its points
//       walked together, so every node and triangle is fetched once for all of them; points
//       whose value is too near the decision go to the verify list;
//   SDF_SIGN_EXACT: one point of the verify list per invocation: the exact winding number.
#version 450 core
#extension GL_ARB_shader_group_vote : enable

#include "glsl/SdfBakeGlsl.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kBakeLocalSize) in;

#ifdef SDF_SIGN_COARSE
layout(std430, binding = kBakeCoarseBinding) buffer Coarse { CoarsePoint coarse[]; };
#else
layout(std430, binding = kBakeDistanceBinding) buffer Distances { float phi[]; };
layout(std430, binding = kBakePendingBinding) readonly buffer Pending {
    PendingHeader pending;
    uvec2 pendingBlocks[]; // (block index, mask of its pending points)
};
layout(std430, binding = kBakeVerifyBinding) buffer Verify {
    PendingHeader verify;
    uint verifyPoints[]; // grid point indices
};
#endif

uniform uint itemCount;     // coarse points, pending blocks or verify points in the list
uniform uint triangleCount; // for the exact sum
uniform float beta;         // far-field test: |q - center| > beta * radius (Barill et al. sec. 3.2)
uniform float verifyBand;   // an approximate value this close to the decision is recomputed exactly
uniform uint parity;        // 1: inside where round(w) is odd (closed meshes); 0: where w > 0.5

// atan(y, x) without branches, to about 2e-7 relative: the argument reduction and polynomial of
// Cephes' atanf (Moshier 1989). llvmpipe's built-in two-argument atan runs several times slower
// inside the loops over triangles below.
float atan2Reduced(float y, float x) {
    float ax = abs(x), ay = abs(y);
    float r = min(ax, ay) / max(max(ax, ay), 1.0e-30); // in [0, 1]
    bool upper = r > 0.41421356;                        // tan(pi / 8)
    float t = upper ? (r - 1.0) / (r + 1.0) : r;        // atan(r) = pi / 4 + atan(t) when upper
    float z = t * t;
    float a = (upper ? 0.78539816 : 0.0) +
              ((((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z -
                3.33329491539e-1) * z * t + t);
    a = ay > ax ? 1.57079633 - a : a;
    a = x < 0.0 ? 3.14159265 - a : a;
    return y < 0.0 ? -a : a;
}

// Signed solid angle of triangle (a, b, c) seen from the origin: Van Oosterom & Strackee 1983,
// tan(Omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|).
float solidAngle(vec3 a, vec3 b, vec3 c) {
    float la = length(a), lb = length(b), lc = length(c);
    float num = dot(a, cross(b, c));
    float den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    return 2.0 * atan2Reduced(num, den);
}

const float kBakePi = 3.14159265358979;

// Fast winding number at p (Barill et al. 2018): exact solid angles of the triangles of near
// leaves, and for a node farther than beta times its radius (sec. 3.2) its dipole term
// (p~ - q) . n~ / |p~ - q|^3 (eq. 14, in units of 4 pi). Walks the preorder links like walkBlock
// (glsl/SdfBakeGlsl.h); the order is fixed per point, so the float sum is the same on every
// run.
float fastWindingNumber(vec3 p) {
    float sum = 0.0; // [sr]
    uint n = 0u;
    while (n < nodeCount) {
        uint leaf = 0u;
        while (n < nodeCount) {
            uvec4 c = texelFetch(windingNodes, int(2u * n));
            uvec4 d = texelFetch(windingNodes, int(2u * n + 1u));
            vec3 q = uintBitsToFloat(c.xyz) - p;
            float dist = length(q);
            bool far = dist > beta * uintBitsToFloat(c.w);
            sum += far ? dot(q, uintBitsToFloat(d.xyz)) / (dist * dist * dist) : 0.0;
            if (!far && linkCount(d.w) != 0u) {
                leaf = d.w;
                break;
            }
            // Near internal node: its first child; far subtree: past it (a leaf's is n + 1).
            n = !far || linkCount(d.w) != 0u ? n + 1u : linkIndex(d.w);
        }
        for (uint t = linkIndex(leaf); t < linkIndex(leaf) + linkCount(leaf); ++t) {
            vec3 a, b, c;
            fetchTriangle(t, a, b, c);
            sum += solidAngle(a - p, b - p, c - p);
        }
        n = n + 1u;
    }
    return sum / (4.0 * kBakePi);
}

// Exact generalized winding number at p (Jacobson et al. 2013): every triangle's solid angle,
// in leaf order. `count` triangles: 0 costs nothing but the loop's first, masked pass.
float exactWindingNumber(vec3 p, uint count) {
    float sum = 0.0;
    for (uint t = 0u; t < count; ++t) {
        vec3 a, b, c;
        fetchTriangle(t, a, b, c);
        sum += solidAngle(a - p, b - p, c - p);
    }
    return sum / (4.0 * kBakePi);
}

// Distance of w from the value where the decision flips (0.5 for winding, the half-integers
// for parity).
float margin(float w) {
    return parity != 0u ? abs(fract(abs(w)) - 0.5) : abs(w - 0.5);
}

bool isInside(float w) {
    return parity != 0u ? (int(round(abs(w))) & 1) == 1 : w > 0.5;
}

const int kDepth = kBakeBlockDepth;
const int kPoints = 4 * kDepth;

// Solid angles of one triangle seen from the 4 points of a layer at height z.
vec4 layerSolidAngles(vec3 a, vec3 b, vec3 c, vec3 q0, vec3 q1, float z) {
    vec4 omega;
    for (int k = 0; k < 4; ++k) {
        vec3 p = layerPoint(q0, q1, z, k);
        omega[k] = solidAngle(a - p, b - p, c - p);
    }
    return omega;
}

// The fast winding numbers [sr] of a block's 16 points (blockPoints, glsl/SdfBakeGlsl.h),
// walked together: a node counts as far only if it is far from every point of the block (its
// centroid farther than beta radii from the block's box), so each point's sum is at least as
// exact as its own walk would give.
void blockWindingNumbers(vec3 q0, vec3 q1, float z[kDepth], out vec4 w[kDepth]) {
    vec3 boxLo = q0, boxHi = vec3(q1.xy, z[kDepth - 1]);
    for (int j = 0; j < kDepth; ++j)
        w[j] = vec4(0.0);
    uint n = 0u;
    while (n < nodeCount) {
        uint leaf = 0u;
        while (n < nodeCount) {
            uvec4 c = texelFetch(windingNodes, int(2u * n));
            uvec4 d = texelFetch(windingNodes, int(2u * n + 1u));
            vec3 center = uintBitsToFloat(c.xyz);
            float reach = beta * uintBitsToFloat(c.w);
            bool far = boxDistance2(center, boxLo, boxHi) > reach * reach;
            if (far) {
                // Barill et al. 2018, eq. 14 (first order): (p~ - q) . n~ / |p~ - q|^3.
                vec3 dipole = uintBitsToFloat(d.xyz);
                for (int j = 0; j < kDepth; ++j)
                    for (int k = 0; k < 4; ++k) {
                        vec3 q = center - layerPoint(q0, q1, z[j], k);
                        float dist2 = dot(q, q);
                        w[j][k] += dot(q, dipole) / (dist2 * sqrt(dist2));
                    }
            }
            if (!far && linkCount(d.w) != 0u) {
                leaf = d.w;
                break;
            }
            // Near internal node: its first child; far subtree: past it (a leaf's is n + 1).
            n = !far || linkCount(d.w) != 0u ? n + 1u : linkIndex(d.w);
        }
        for (uint t = linkIndex(leaf); t < linkIndex(leaf) + linkCount(leaf); ++t) {
            vec3 a, b, c;
            fetchTriangle(t, a, b, c);
            for (int j = 0; j < kDepth; ++j)
                w[j] += layerSolidAngles(a, b, c, q0, q1, z[j]);
        }
        n = n + 1u;
    }
}

#if defined(SDF_SIGN_COARSE)

void main() {
    uint item = SLUICE_GLOBAL_ID.x;
    if (item >= itemCount)
        return;
    uint index = coarseSignEntry(item);
    vec3 p = coarseItemPoint(index);
    float d = coarse[index].distance;
    if (d == 0.0) // on the surface: no sign
        return;
    float w = fastWindingNumber(p);
    // The far field can be off by a little; near the decision value, pay for the exact sum.
    float exact = exactWindingNumber(p, margin(w) < verifyBand ? triangleCount : 0u);
    if (margin(w) < verifyBand)
        w = exact;
    if (isInside(w))
        coarse[index].distance = -d;
}

#elif defined(SDF_SIGN_EXACT)

void main() {
    uint item = SLUICE_GLOBAL_ID.x;
    if (item >= itemCount)
        return;
    uint index = verifyPoints[item];
    vec3 p = phiIndexPoint(index);
    if (isInside(exactWindingNumber(p, triangleCount)))
        phi[index] = -phi[index];
}

#else

void main() {
    uint item = SLUICE_GLOBAL_ID.x;
    if (item >= itemCount)
        return;
    uvec2 entry = pendingBlocks[item];
    uvec3 origin = pendingBlockOrigin(entry.x);
    vec3 q0, q1;
    float z[kDepth];
    blockPoints(origin, q0, q1, z);
    uint mask = entry.y;

    vec4 w[kDepth]; // [sr], layer by layer
    blockWindingNumbers(q0, q1, z, w);

    // The far field can be off by a little: a point whose value is near the decision goes to
    // the verify list (SDF_SIGN_EXACT sums every triangle for it); the others are decided here.
    uint verifyMask = 0u, insideMask = 0u;
    for (int k = 0; k < kPoints; ++k) {
        float wk = w[k >> 2][k & 3] / (4.0 * kBakePi);
        bool verifyPoint = margin(wk) < verifyBand;
        verifyMask |= verifyPoint ? 1u << k : 0u;
        insideMask |= !verifyPoint && isInside(wk) ? 1u << k : 0u;
    }
    verifyMask &= mask;
    insideMask &= mask;
    // Stores after the loop above (llvmpipe runs them much faster that way).
    for (int k = 0; k < kPoints; ++k)
        if ((insideMask & (1u << k)) != 0u) {
            uint index = blockPointIndex(entry.x, origin, k);
            phi[index] = -phi[index];
        }
    uint slot = atomicAdd(verify.count, uint(bitCount(verifyMask)));
    for (int k = 0; k < kPoints; ++k)
        if ((verifyMask & (1u << k)) != 0u)
            verifyPoints[slot + uint(bitCount(verifyMask & ((1u << k) - 1u)))] =
                blockPointIndex(entry.x, origin, k);
}

#endif
