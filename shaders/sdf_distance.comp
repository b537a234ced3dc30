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
uniform uint bvhDepth;   // levels below the root

// Squared distance from p to segment (a, b), both relative to p's frame.
float segmentDistance2(vec3 p, vec3 a, vec3 b) {
    vec3 ab = b - a, ap = p - a;
    float t = clamp(dot(ap, ab) / max(dot(ab, ab), 1.0e-30), 0.0, 1.0);
    vec3 e = ap - ab * t;
    return dot(e, e);
}

// Squared distance from p to triangle (a, b, c), without branches: the distance to the plane
// where p projects inside the triangle, else the nearest of the three edges. The same closest
// point as Ericson's case analysis (Real-Time Collision Detection, 5.1.5) used by the reference;
// written branch-free because llvmpipe runs divergent branches inside the BVH walk very slowly.
// Everything is relative to a corner, so the numbers stay as small as the triangle and its
// distance to p.
float pointTriangleDistance2(vec3 p, vec3 a, vec3 b, vec3 c) {
    vec3 ab = b - a, bc = c - b, ca = a - c;
    vec3 ap = p - a, bp = p - b, cp = p - c;
    vec3 n = cross(ab, -ca);
    bool inside = dot(cross(ab, ap), n) >= 0.0 && dot(cross(bc, bp), n) >= 0.0 &&
                  dot(cross(ca, cp), n) >= 0.0;
    float plane = dot(ap, n);
    float edges = min(segmentDistance2(p, a, b),
                      min(segmentDistance2(p, b, c), segmentDistance2(p, c, a)));
    return inside ? plane * plane / dot(n, n) : edges;
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
    // A first bound from the leaf reached by always stepping into the child with the nearer box
    // (first child: the next node; second: `first`), so the walk below prunes from the start.
    // A for loop bounded by the tree depth, not a while loop on node data: llvmpipe is much
    // faster with it.
    uint n = 0u;
    for (uint level = 0u; level < bvhDepth; ++level) {
        if (nodes[n].count != 0u)
            break;
        uint second = nodes[n].first;
        n = boxDistance2(p, n + 1u) <= boxDistance2(p, second) ? n + 1u : second;
    }
    float best = 3.0e38;
    uint leafFirst = nodes[n].first;
    for (uint t = leafFirst; t < leafFirst + nodes[n].count; ++t)
        best = min(best, pointTriangleDistance2(p, triangles[t].a.xyz, triangles[t].b.xyz,
                                                triangles[t].c.xyz));

    uint nodeCount = uint(nodes.length());
    n = 0u;
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
