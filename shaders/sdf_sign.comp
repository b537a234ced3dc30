// Sign of every grid point of a z-slab from the fast winding number over the BVH (Barill et al.
// 2018): exact solid angles for near nodes, the dipole expansion for far ones. Reads the
// unsigned distance written by sdf_distance.comp and negates it inside.
#version 450 core

#include "shared/SdfBake.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kBakeLocalSize, local_size_y = kBakeLocalSize,
       local_size_z = kBakeLocalSize) in;

layout(std430, binding = kBakeNodesBinding) readonly buffer Nodes { BvhNode nodes[]; };
layout(std430, binding = kBakeTrianglesBinding) readonly buffer Triangles {
    BvhTriangle triangles[];
};
layout(std430, binding = kBakeDistanceBinding) buffer Distances { float phi[]; };

uniform uvec3 dims;      // [grid points]
uniform uint sliceBegin; // first z slice of this slab
uniform uint sliceEnd;   // one past the last
uniform float beta;      // far-field test: |q - center| > beta * radius (Barill et al. sec. 3.2)
uniform float verifyBand; // an approximate value this close to the decision is recomputed exactly
uniform uint parity;     // 1: inside where round(w) is odd (closed meshes); 0: inside where w > 0.5

const float kPi = 3.14159265358979;

// Signed solid angle of triangle (a, b, c) seen from the origin: Van Oosterom & Strackee 1983,
// tan(Omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|).
float solidAngle(vec3 a, vec3 b, vec3 c) {
    float la = length(a), lb = length(b), lc = length(c);
    float num = dot(a, cross(b, c));
    float den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    return 2.0 * atan(num, den);
}

// Winding number at p. With `exact`, every triangle is summed; otherwise far nodes contribute
// their dipole term (p~ - q) . n~ / |p~ - q|^3 (Barill et al. 2018, eq. 14, in units of 4 pi).
// Walks the preorder skip links, like sdf_distance.comp. The order is fixed per point, so the
// float sum is the same on every run.
float windingNumber(vec3 p, bool exact) {
    float sum = 0.0; // [sr]
    uint nodeCount = uint(nodes.length());
    uint n = 0u;
    while (n < nodeCount) {
        vec3 d = nodes[n].center.xyz - p;
        float dist = length(d);
        uint count = nodes[n].count;
        if (!exact && dist > beta * nodes[n].center.w) {
            sum += dot(d, nodes[n].dipole.xyz) / (dist * dist * dist);
            n = nodes[n].skip;
        } else if (count > 0u) {
            uint first = nodes[n].first;
            for (uint t = first; t < first + count; ++t)
                sum += solidAngle(triangles[t].a.xyz - p, triangles[t].b.xyz - p,
                                  triangles[t].c.xyz - p);
            n = nodes[n].skip;
        } else {
            n = n + 1u;
        }
    }
    return sum / (4.0 * kPi);
}

// Distance of w from the value where the decision flips (0.5 for winding, the half-integers
// for parity).
float margin(float w) {
    return parity != 0u ? abs(fract(abs(w)) - 0.5) : abs(w - 0.5);
}

bool isInside(float w) {
    return parity != 0u ? (int(round(abs(w))) & 1) == 1 : w > 0.5;
}

void main() {
    uvec3 id = SLUICE_GLOBAL_ID;
    uint k = id.z + sliceBegin;
    if (id.x >= dims.x || id.y >= dims.y || k >= sliceEnd)
        return;
    uint index = id.x + dims.x * (id.y + dims.y * k);
    float d = phi[index];
    if (d == 0.0) // on the surface: no sign
        return;
    vec3 p = vec3(id.x, id.y, k);
    float w = windingNumber(p, false);
    // The far field can be off by a little; near the decision value, pay for the exact sum.
    if (margin(w) < verifyBand)
        w = windingNumber(p, true);
    if (isInside(w))
        phi[index] = -d;
}
