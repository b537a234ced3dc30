// Per stored block: the triangles of each cell whose lowest corner it holds, over the cell's
// six Kuhn tetrahedra, at its block's base plus a work-group scan, in a fixed order. A vertex
// is found by the edge it lies on: its owner (the edge's lower end) keeps its first vertex and
// its crossing edges. Each triangle faces out of the fluid (down the field).
#version 450 core

#include "shared/SurfaceGlsl.h"

layout(local_size_x = kSurfaceBlockSamples) in;

layout(std430, binding = kSurfBindTriBase) readonly buffer TriBase { uint triBase[]; };
layout(std430, binding = kSurfBindSampleVert) readonly buffer SampleVert { uint sampleVert[]; };
layout(std430, binding = kSurfBindSampleEdges) readonly buffer SampleEdges { uint sampleEdges[]; };
layout(std430, binding = kSurfBindTriangles) writeonly buffer Triangles { uint triangles[]; };

// The vertex on the edge between cell corners a and b (one holds the other's bits).
uint edgeVertex(ivec3 s, uint a, uint b) {
    uint lo = bitCount(a) < bitCount(b) ? a : b;
    uint d = a ^ b;
    uint owner = sampleSlot(s + cornerOffset(lo));
    uint edges = sampleEdges[owner];
    return sampleVert[owner] + bitCount(edges & ((1u << (d - 1u)) - 1u));
}

uint written = 0u;

// Writes the triangle on the edges (a0, b0), (a1, b1), (a2, b2) of the cell at s, facing away
// from `inward`. The facing is decided on the edges' midpoints in cell corners: the triangle
// through the interpolated vertices faces the same way (its corners stay inside distinct
// edges, so it never flips), and the midpoints never make a degenerate triangle.
void emit(uint base, ivec3 s, uvec2 e0, uvec2 e1, uvec2 e2, vec3 inward) {
    vec3 m0 = 0.5 * vec3(cornerOffset(e0.x) + cornerOffset(e0.y));
    vec3 m1 = 0.5 * vec3(cornerOffset(e1.x) + cornerOffset(e1.y));
    vec3 m2 = 0.5 * vec3(cornerOffset(e2.x) + cornerOffset(e2.y));
    uint v0 = edgeVertex(s, e0.x, e0.y);
    uint v1 = edgeVertex(s, e1.x, e1.y);
    uint v2 = edgeVertex(s, e2.x, e2.y);
    uint at = 3u * (base + written);
    triangles[at] = v0;
    if (dot(cross(m1 - m0, m2 - m0), inward) > 0.0) { // facing into the fluid: turn it round
        triangles[at + 1u] = v2;
        triangles[at + 2u] = v1;
    } else {
        triangles[at + 1u] = v1;
        triangles[at + 2u] = v2;
    }
    ++written;
}

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockSamples;
    uint lane = gl_LocalInvocationID.x;
    bool live = slot < uCount;
    ivec3 s = ivec3(0);
    uint inside = 0u;
    uint count = 0u;
    if (live) {
        s = blockCoord(activeBlock[slot]) * int(kSurfaceBlockSide) + laneCoord(lane);
        if (all(lessThan(s, uSamples))) {
            inside = cellInsideMask(s);
            count = cellTriangles(inside);
        }
    }
    uint total;
    uint first = groupExclusiveScan(lane, count, total);
    if (!live || count == 0u)
        return;
    uint base = triBase[slot] + first;
    for (uint t = 0u; t < 6u; ++t) {
        uint in4[4];
        uint out4[4];
        uint nIn = 0u;
        uint nOut = 0u;
        vec3 sumIn = vec3(0.0);
        vec3 sumOut = vec3(0.0);
        for (uint v = 0u; v < 4u; ++v) {
            uint c = kTetCorners[4u * t + v];
            if (((inside >> c) & 1u) != 0u) {
                in4[nIn++] = c;
                sumIn += vec3(cornerOffset(c));
            } else {
                out4[nOut++] = c;
                sumOut += vec3(cornerOffset(c));
            }
        }
        if (nIn == 0u || nOut == 0u)
            continue;
        vec3 inward = sumIn / float(nIn) - sumOut / float(nOut);
        if (nIn == 1u) {
            emit(base, s, uvec2(in4[0], out4[0]), uvec2(in4[0], out4[1]), uvec2(in4[0], out4[2]),
                 inward);
        } else if (nIn == 3u) {
            emit(base, s, uvec2(out4[0], in4[0]), uvec2(out4[0], in4[1]), uvec2(out4[0], in4[2]),
                 inward);
        } else {
            uvec2 q0 = uvec2(in4[0], out4[0]);
            uvec2 q2 = uvec2(in4[1], out4[1]);
            emit(base, s, q0, uvec2(in4[0], out4[1]), q2, inward);
            emit(base, s, q0, q2, uvec2(in4[1], out4[0]), inward);
        }
    }
}
