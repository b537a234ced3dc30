// Unsigned distance from every grid point of a z-slab to the nearest triangle, through the BVH.
// Coordinates are grid-relative voxels (shared/SdfBake.h); writes phi = distance [voxels].
#version 450 core

#include "shared/SdfBake.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kBakeLocalSize, local_size_y = kBakeLocalSize,
       local_size_z = kBakeLocalSize) in;

layout(std430, binding = kBakeNodesBinding) readonly buffer Nodes { BvhNode nodes[]; };
layout(std430, binding = kBakeTrianglesBinding) readonly buffer Triangles {
    BvhTriangle triangles[];
};
layout(std430, binding = kBakeDistanceBinding) writeonly buffer Distances { float phi[]; };

uniform uvec3 dims;      // [grid points]
uniform uint sliceBegin; // first z slice of this slab
uniform uint sliceEnd;   // one past the last

// Squared distance from p to triangle (a, b, c): Ericson, Real-Time Collision Detection, 5.1.5,
// the same case analysis as the CPU reference. Everything is relative to a corner, so the
// numbers stay as small as the triangle and its distance to p.
float pointTriangleDistance2(vec3 p, vec3 a, vec3 b, vec3 c) {
    vec3 ab = b - a, ac = c - a, ap = p - a;
    float d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0)
        return dot(ap, ap);
    vec3 bp = p - b;
    float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3)
        return dot(bp, bp);
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        vec3 e = ap - ab * (d1 / (d1 - d3));
        return dot(e, e);
    }
    vec3 cp = p - c;
    float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6)
        return dot(cp, cp);
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        vec3 e = ap - ac * (d2 / (d2 - d6));
        return dot(e, e);
    }
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        vec3 e = bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
        return dot(e, e);
    }
    float denom = 1.0 / (va + vb + vc);
    vec3 e = ap - ab * (vb * denom) - ac * (vc * denom);
    return dot(e, e);
}

float boxDistance2(vec3 p, uint node) {
    vec3 d = max(max(nodes[node].boxMin.xyz - p, p - nodes[node].boxMax.xyz), vec3(0.0));
    return dot(d, d);
}

// Squared distance from p to the nearest triangle: a depth-first walk along the preorder skip
// links (no stack; llvmpipe runs dynamically indexed local arrays very slowly) that prunes a
// subtree once its box is no closer than the best triangle so far. min() is exact, so the
// result does not depend on the visiting order.
float nearestDistance2(vec3 p) {
    float best = 3.0e38;
    uint nodeCount = uint(nodes.length());
    uint n = 0u;
    while (n < nodeCount) {
        uint count = nodes[n].count;
        if (boxDistance2(p, n) >= best) {
            n = nodes[n].skip;
        } else if (count > 0u) {
            uint first = nodes[n].first;
            for (uint t = first; t < first + count; ++t)
                best = min(best, pointTriangleDistance2(p, triangles[t].a.xyz, triangles[t].b.xyz,
                                                        triangles[t].c.xyz));
            n = nodes[n].skip;
        } else {
            n = n + 1u;
        }
    }
    return best;
}

void main() {
    uvec3 id = SLUICE_GLOBAL_ID;
    uint k = id.z + sliceBegin;
    // Every invocation runs the search (on a clamped point), so all lanes of a SIMD batch leave
    // the loop together; only those on the grid write.
    bool onGrid = id.x < dims.x && id.y < dims.y && k < sliceEnd;
    vec3 p = vec3(min(id.x, dims.x - 1u), min(id.y, dims.y - 1u), min(k, sliceEnd - 1u));
    float d = sqrt(nearestDistance2(p));
    if (onGrid)
        phi[id.x + dims.x * (id.y + dims.y * k)] = d;
}
