// GLSL helpers of the PBF passes for the colliders (docs/pbf.md, "Collision with one collider"):
// the collider records, a body's reach, the SDF buffer and its texel view, sampling a dense or
// sparse grid as format::SdfSampler does, the boundary share of a flat boundary, and the
// collision push-out with friction. Included by glsl/PbfGlsl.h (after the parameter block and
// the kernels); only with PBF_WITH_COLLIDERS.
#ifndef SLUICE_GLSL_COLLIDERS_GLSL_H
#define SLUICE_GLSL_COLLIDERS_GLSL_H

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

#endif // SLUICE_GLSL_COLLIDERS_GLSL_H
