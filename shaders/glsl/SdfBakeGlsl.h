// GLSL helpers of the SDF bake passes: BVH and triangle fetches, the coarse grid, blocks, the
// point-triangle distance and the nearest-triangle walk of a block (shared/SdfBake.h has the
// layouts). GLSL only. Shaders including it enable GL_ARB_shader_group_vote where there is one
// (walkBlock votes when it can): `#extension GL_ARB_shader_group_vote : enable`.
//
// Written for llvmpipe as much as for GPUs. llvmpipe runs 8 invocations in the lanes of one SIMD
// register and executes every block of an if (and every loop body at least once) with the
// inactive lanes masked off, whether or not any lane is active: so the walks below are nested
// loops (an inner loop over nodes that stops at the next leaf to open, an outer one that opens
// it), never a leaf's work inside a branch of the node loop.
#ifndef SLUICE_SHARED_SDF_BAKE_GLSL_H
#define SLUICE_SHARED_SDF_BAKE_GLSL_H

#include "shared/SdfBake.h"

#ifndef __cplusplus

layout(binding = kBakeDistanceNodesUnit) uniform usamplerBuffer distanceNodes;
layout(binding = kBakeTrianglesUnit) uniform samplerBuffer triangleCorners;
layout(binding = kBakeWindingNodesUnit) uniform usamplerBuffer windingNodes;

uniform uvec3 dims;     // [grid points]
uniform uint nodeCount; // BVH nodes

uint linkCount(uint link) {
    return link & ((1u << kBvhLinkShift) - 1u);
}
uint linkIndex(uint link) {
    return link >> kBvhLinkShift;
}

// Invocation i of a work group of 64 as a position in 4 x 4 x 4, Morton order: every 8
// consecutive invocations (one SIMD register on llvmpipe) are a 2 x 2 x 2 block.
uvec3 mortonPosition(uint i) {
    return uvec3((i & 1u) | ((i >> 2u) & 2u), ((i >> 1u) & 1u) | ((i >> 3u) & 2u),
                 ((i >> 2u) & 1u) | ((i >> 4u) & 2u));
}

uint gridIndex(uvec3 p) {
    return p.x + dims.x * (p.y + dims.y * p.z);
}

uvec3 coarseDims() {
    return (dims + uint(kBakeCoarseSpacing - 2)) / uint(kBakeCoarseSpacing) + 1u;
}
// Grid point of coarse point c.
uvec3 coarseGridPoint(uvec3 c) {
    return min(c * uint(kBakeCoarseSpacing), dims - 1u);
}

// Blocks: the fine pass gives each invocation an aligned block of 2 x 2 x kBakeBlockDepth grid
// points (the coarse pass the same of coarse points), and the pending list names blocks. A
// block's points are the combinations of x in {q0.x, q1.x}, y in {q0.y, q1.y} and z in
// z[0..kBakeBlockDepth), clamped to the grid, so points past the grid repeat the last ones;
// point k is (k & 1, (k >> 1) & 1, k >> 2) in the block, and layer j holds points 4 j .. 4 j + 3.
const uvec3 kBakeBlockSize = uvec3(2u, 2u, uint(kBakeBlockDepth));

uvec3 blockDims() {
    return (dims + kBakeBlockSize - 1u) / kBakeBlockSize;
}

void blockPoints(uvec3 origin, out vec3 q0, out vec3 q1, out float z[kBakeBlockDepth]) {
    q0 = vec3(min(origin, dims - 1u));
    q1 = vec3(min(origin + 1u, dims - 1u));
    for (int j = 0; j < kBakeBlockDepth; ++j)
        z[j] = float(min(origin.z + uint(j), dims.z - 1u));
}

uvec3 blockPointOffset(int k) {
    return uvec3(k & 1, (k >> 1) & 1, k >> 2);
}

// Point k (0..3) of a layer at height z.
vec3 layerPoint(vec3 q0, vec3 q1, float z, int k) {
    return vec3((k & 1) != 0 ? q1.x : q0.x, (k & 2) != 0 ? q1.y : q0.y, z);
}

// Which points a program variant computes, and where their values go:
//   dense (default): the whole grid; phi[] and coarse[] x fastest over the grid and the coarse
//       grid, pending entries are block indices (x fastest over the grid of blocks);
//   SDF_SPARSE: the bricks of a list (shared/SdfBake.h); block slot s is block mortonPosition(s %
//       32) of brick s / 32, its point k is phi[16 s + k], pending entries are slots, and brick b's
//       coarse point c (0..2 per axis) is coarse[27 b + c.x + 3 (c.y + 3 c.z)], signed and read
//       through the first entry at its grid point (coarseRep);
//   SDF_POINTS: a list of query points, coarse[i] for point i (the coarse passes only).
// Verify entries are indices into phi[].
#if defined(SDF_SPARSE)
layout(std430, binding = kBakeBrickBinding) readonly buffer Bricks { uvec4 bricks[]; };
layout(std430, binding = kBakeCoarseRepBinding) readonly buffer CoarseRep { uint coarseRep[]; };
uniform uint brickCount; // bricks in the list

const uint kBrickBlocks = uint(kBakeBrickSize * kBakeBrickSize * kBakeBrickSize) /
                          uint(4 * kBakeBlockDepth);
const uint kBrickCoarsePoints = uint(kBakeBrickCoarse * kBakeBrickCoarse * kBakeBrickCoarse);

// Lower corner of brick b [grid points]; indices past the list repeat the last brick, so every
// lane runs the same loops.
uvec3 brickOrigin(uint b) {
    return bricks[min(b, brickCount - 1u)].xyz;
}
uint brickCoarseIndex(uint b, uvec3 c) {
    uint side = uint(kBakeBrickCoarse);
    return b * kBrickCoarsePoints + c.x + side * (c.y + side * c.z);
}
uvec3 brickCoarsePoint(uint b, uvec3 c) {
    return min(brickOrigin(b) + c * uint(kBakeCoarseSpacing), dims - 1u);
}
// Block g of the bricks' coarse points, as the coarse passes walk them: four per brick (brick
// g / 4), each 2 x 2 x 4 coarse points from c0 with the third column, row and layer repeated to
// fill it. Point k of the block is coarse point c0 + blockPointOffset(k) where that is <= 2 on
// every axis (blockCoarsePoint), a repeat otherwise.
void brickCoarseBlock(uint g, out uint brick, out uvec3 c0, out vec3 q0, out vec3 q1,
                      out float z[kBakeBlockDepth]) {
    brick = g / 4u;
    c0 = uvec3((g & 1u) * 2u, ((g >> 1u) & 1u) * 2u, 0u);
    uvec3 cMax = uvec3(kBakeBrickCoarse - 1);
    q0 = vec3(brickCoarsePoint(brick, c0));
    q1 = vec3(brickCoarsePoint(brick, min(c0 + 1u, cMax)));
    for (int j = 0; j < kBakeBlockDepth; ++j)
        z[j] = float(brickCoarsePoint(brick, uvec3(0u, 0u, min(uint(j), cMax.z))).z);
}
// Whether point k of a coarse block from c0 is a coarse point of its own (not a repeat).
bool blockCoarsePoint(uvec3 c0, int k) {
    return all(lessThanEqual(c0 + blockPointOffset(k), uvec3(kBakeBrickCoarse - 1)));
}
uvec3 slotOrigin(uint slot) {
    return brickOrigin(slot / kBrickBlocks) + mortonPosition(slot % kBrickBlocks) * kBakeBlockSize;
}
#elif defined(SDF_POINTS)
layout(std430, binding = kBakeBrickBinding) readonly buffer Queries { vec4 queryPoints[]; };
#endif

// The coarse entry the coarse sign pass signs as its item `item`: every entry of the dense grid
// or the query points; the first entry of each distinct point of the bricks (coarseRep).
uint coarseSignEntry(uint item) {
#if defined(SDF_SPARSE)
    return coarseRep[brickCount * kBrickCoarsePoints + item];
#else
    return item;
#endif
}

// Position of coarse entry `item` [voxels].
vec3 coarseItemPoint(uint item) {
#if defined(SDF_SPARSE)
    uint c = item % kBrickCoarsePoints;
    uint side = uint(kBakeBrickCoarse);
    return vec3(brickCoarsePoint(item / kBrickCoarsePoints,
                                 uvec3(c % side, (c / side) % side, c / (side * side))));
#elif defined(SDF_POINTS)
    return queryPoints[item].xyz;
#else
    uvec3 cd = coarseDims();
    return vec3(coarseGridPoint(uvec3(item % cd.x, (item / cd.x) % cd.y, item / (cd.x * cd.y))));
#endif
}

// Lower corner of the block a pending entry names [grid points].
uvec3 pendingBlockOrigin(uint entry) {
#if defined(SDF_SPARSE)
    return slotOrigin(entry);
#else
    uvec3 bd = blockDims();
    return uvec3(entry % bd.x, (entry / bd.x) % bd.y, entry / (bd.x * bd.y)) * kBakeBlockSize;
#endif
}

// Index in phi[] of point k of the block a pending entry names, whose corner is `origin`.
uint blockPointIndex(uint entry, uvec3 origin, int k) {
#if defined(SDF_SPARSE)
    return uint(4 * kBakeBlockDepth) * entry + uint(k);
#else
    return gridIndex(origin + blockPointOffset(k));
#endif
}

// Grid point of phi[index].
vec3 phiIndexPoint(uint index) {
#if defined(SDF_SPARSE)
    uint k = index % uint(4 * kBakeBlockDepth);
    return vec3(min(slotOrigin(index / uint(4 * kBakeBlockDepth)) + blockPointOffset(int(k)),
                    dims - 1u));
#else
    return vec3(index % dims.x, (index / dims.x) % dims.y, index / (dims.x * dims.y));
#endif
}

void fetchTriangle(uint t, out vec3 a, out vec3 b, out vec3 c) {
    a = texelFetch(triangleCorners, int(3u * t)).xyz;
    b = texelFetch(triangleCorners, int(3u * t + 1u)).xyz;
    c = texelFetch(triangleCorners, int(3u * t + 2u)).xyz;
}

// Squared distance from p to the box [lo, hi]; 0 inside.
float boxDistance2(vec3 p, vec3 lo, vec3 hi) {
    vec3 d = max(max(lo - p, p - hi), vec3(0.0));
    return dot(d, d);
}

// The parts of the point-triangle distance that do not depend on the point, computed once per
// triangle and shared by every point an invocation owns.
struct TriangleTerms {
    vec3 a, b, c;
    vec3 ab, bc, ca;     // edges
    vec3 n;              // normal (ab x ac), not normalized
    vec3 mab, mbc, mca;  // n x edge: a point is on the inner side of an edge where dot >= 0
    float iab, ibc, ica; // 1 / |edge|^2
    float inn;           // 1 / |n|^2, 0 for a triangle too thin for float
};

TriangleTerms triangleTerms(vec3 a, vec3 b, vec3 c) {
    TriangleTerms t;
    t.a = a;
    t.b = b;
    t.c = c;
    t.ab = b - a;
    t.bc = c - b;
    t.ca = a - c;
    t.n = cross(t.ab, -t.ca);
    t.mab = cross(t.n, t.ab);
    t.mbc = cross(t.n, t.bc);
    t.mca = cross(t.n, t.ca);
    t.iab = 1.0 / max(dot(t.ab, t.ab), 1.0e-30);
    t.ibc = 1.0 / max(dot(t.bc, t.bc), 1.0e-30);
    t.ica = 1.0 / max(dot(t.ca, t.ca), 1.0e-30);
    float nn = dot(t.n, t.n);
    t.inn = nn > 0.0 ? 1.0 / nn : 0.0;
    return t;
}

// Squared distance from p to the triangle, without branches: the distance to the plane where p
// projects inside the triangle, else the nearest of the three edges. The same closest point as
// Ericson's case analysis (Real-Time Collision Detection, 5.1.5) used by the CGAL reference.
// Everything is relative to a corner, so the numbers stay as small as the triangle and its
// distance to p.
float triangleDistance2(TriangleTerms t, vec3 p) {
    vec3 ap = p - t.a, bp = p - t.b, cp = p - t.c;
    // (ab x ap) . n = ap . (n x ab): the side of each edge p is on.
    bool inside =
        t.inn > 0.0 && dot(ap, t.mab) >= 0.0 && dot(bp, t.mbc) >= 0.0 && dot(cp, t.mca) >= 0.0;
    float plane = dot(ap, t.n);
    vec3 eab = ap - t.ab * clamp(dot(ap, t.ab) * t.iab, 0.0, 1.0);
    vec3 ebc = bp - t.bc * clamp(dot(bp, t.bc) * t.ibc, 0.0, 1.0);
    vec3 eca = cp - t.ca * clamp(dot(cp, t.ca) * t.ica, 0.0, 1.0);
    float edges = min(dot(eab, eab), min(dot(ebc, ebc), dot(eca, eca)));
    return inside ? plane * plane * t.inn : edges;
}

// Squared distances from the 4 points of a layer at height z to one triangle.
vec4 layerDistances(TriangleTerms t, vec3 q0, vec3 q1, float z) {
    return vec4(triangleDistance2(t, layerPoint(q0, q1, z, 0)),
                triangleDistance2(t, layerPoint(q0, q1, z, 1)),
                triangleDistance2(t, layerPoint(q0, q1, z, 2)),
                triangleDistance2(t, layerPoint(q0, q1, z, 3)));
}

// Folds triangle `index` into a block's squared distances and nearest triangles (best[j] and
// nearest[j]: the 4 points of layer j). Ties keep the earlier triangle.
void blockTriangle(uint index, vec3 q0, vec3 q1, float z[kBakeBlockDepth],
                   inout vec4 best[kBakeBlockDepth], inout uvec4 nearest[kBakeBlockDepth]) {
    vec3 a, b, c;
    fetchTriangle(index, a, b, c);
    TriangleTerms t = triangleTerms(a, b, c);
    for (int j = 0; j < kBakeBlockDepth; ++j) {
        vec4 d = layerDistances(t, q0, q1, z[j]);
        nearest[j] = mix(nearest[j], uvec4(index), lessThan(d, best[j]));
        best[j] = min(best[j], d);
    }
}

// The nearest triangles of a block's points, starting from the bounds in `best`: a depth-first
// walk along the preorder links, per invocation, that opens a node when its box is nearer than
// the best triangle so far of any of the block's points. min() is exact and ties keep the first
// triangle of the fixed walk order, so the result depends on nothing but the points and bounds.
void walkBlock(vec3 q0, vec3 q1, float z[kBakeBlockDepth], inout vec4 best[kBakeBlockDepth],
               inout uvec4 nearest[kBakeBlockDepth]) {
    uint n = 0u;
    while (n < nodeCount) {
        // Inner loop: on to the next leaves nearer than the best so far. A lane that found one
        // keeps looking for a second while others still search for their first, so fewer lanes
        // idle (Aila & Laine 2009, speculative traversal).
        uint leafA = 0u, leafB = 0u;
        while (n < nodeCount) {
            uvec4 lo = texelFetch(distanceNodes, int(2u * n));
            uvec4 hi = texelFetch(distanceNodes, int(2u * n + 1u));
            vec3 boxLo = uintBitsToFloat(lo.xyz), boxHi = uintBitsToFloat(hi.xyz);
            // Squared box distance of each point: a sum of one per-axis term of each axis.
            vec2 qx = vec2(q0.x, q1.x), qy = vec2(q0.y, q1.y);
            vec2 dx = max(max(boxLo.x - qx, qx - boxHi.x), vec2(0.0));
            vec2 dy = max(max(boxLo.y - qy, qy - boxHi.y), vec2(0.0));
            dx *= dx;
            dy *= dy;
            vec4 xy = vec4(dx.x + dy.x, dx.y + dy.x, dx.x + dy.y, dx.y + dy.y);
            bool near = false;
            for (int j = 0; j < kBakeBlockDepth; ++j) {
                float dz = max(max(boxLo.z - z[j], z[j] - boxHi.z), 0.0);
                near = near || any(lessThan(xy + dz * dz, best[j]));
            }
            bool isLeaf = linkCount(hi.w) != 0u;
            bool found = near && isLeaf;
            leafB = found && leafA != 0u ? hi.w : leafB;
            leafA = found && leafA == 0u ? hi.w : leafA;
            // Near internal node: its first child; far subtree: past it (a leaf's is n + 1).
            n = near || isLeaf ? n + 1u : linkIndex(hi.w);
            if (leafB != 0u)
                break;
#ifdef GL_ARB_shader_group_vote
            if (allInvocationsARB(leafA != 0u || n >= nodeCount))
                break;
#else
            if (leafA != 0u)
                break;
#endif
        }
        uint countA = linkCount(leafA);
        for (uint i = 0u; i < countA + linkCount(leafB); ++i)
            blockTriangle(i < countA ? linkIndex(leafA) + i : linkIndex(leafB) + i - countA, q0, q1,
                          z, best, nearest);
    }
}

#endif // GLSL

#endif // SLUICE_SHARED_SDF_BAKE_GLSL_H
