// Builds a static collider's volume map (docs/pbf.md, "Volume maps"): at each grid point q of
// collider uCollider, the share of a poly6 support of radius uSupport the collider's solid fills,
// less the share of the flat boundary at q's phi along its normal. The solver adds it to the
// flat closed form (BoundaryVolumeGlsl.h), which is exact on flat faces only; this makes edges,
// corners and thin walls right. Both shares are the same quadrature (kVolumeMapSteps points per
// support radius each way, a cell's volume fraction from phi at its centre), so its error on
// flat faces cancels; points farther than uSupport outside the surface or two cells inside it,
// and points where the field is a plane across the support, get 0. One invocation per
// grid point (per voxel of each leaf of a sparse grid: the map is stored per leaf, as its
// samples); run once when a scene loads and again when h changes.
#version 450 core

#define PBF_WITH_COLLIDERS 1
#include "glsl/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

// The SDF buffer again: the map's words lie past every grid's samples (GpuCollider::volumeMap).
layout(std430, binding = kBindVolumeMapOut) writeonly buffer MapOut { float mapOut[]; };

uniform uint uCollider;
uniform float uSupport; // h in the collider's local units [asset units]
uniform uint uStride;   // quadrature cell in grid cells, or 0: support / kVolumeMapSteps
uniform uint uPoints;   // the map's points: the grid's, or 512 per leaf of a sparse grid

// Whether local point q lies in collider c's grid box, where its field holds the geometry (past
// it, sampleCollider extrapolates phi(clamp(q)) + |q - clamp(q)|, which is not the solid's).
bool inGridBox(uint c, vec3 q) {
    return all(greaterThanEqual(q, colliders[c].origin)) &&
           all(lessThanEqual(q, colliders[c].boxMax));
}

#ifdef SLUICE_SPARSE_COLLIDERS
// One read accessor for all of a point's samples of a sparse grid: its cached leaf serves the
// next sample in the same leaf (a fresh accessor a read walked the tree from its root for each
// of the quadrature's ~900 reads).
pnanovdb_readaccessor_t gAcc;
bool gSparse = false;
#endif

// phi at collider c's local point q, as sampleCollider (inside the grid box), a sparse grid's
// samples through the point's accessor.
float sampleAround(uint c, vec3 q) {
#ifdef SLUICE_SPARSE_COLLIDERS
    if (gSparse) {
        vec3 g = (q - colliders[c].origin) / colliders[c].voxelSize;
        vec3 cellLo = clamp(floor(g), vec3(0.0), vec3(colliders[c].dims) - 2.0);
        vec3 t = clamp(g - cellLo, 0.0, 1.0);
        float v[8];
        sparseCorners(gAcc, ivec3(cellLo), v);
        vec3 unused;
        return trilinearCell(v, t, unused);
    }
#endif
    float phi;
    vec3 unused;
    sampleCollider(c, q, phi, unused);
    return phi;
}

// Whether the field around q is the plane of q's phi and normal n, as on a flat face: its
// samples on a lattice of h / 2 over the support (in the grid box) within a hundredth of a
// quadrature cell of the plane's. Most of a collider's band is flat, where the map is 0 and the full quadrature (about
// 900 samples) is skipped; a feature that changes the share (an edge, a corner, the far side of
// a thin wall within the support) moves the field off the plane at these points.
//
// A probe where the sample and the plane are both at least `far` from the surface, on one side,
// agrees whatever their values: the field is a distance, so neither the solid nor the plane
// fills anything within far - d / 2 of it, which covers the lattice's cell around it (0.43
// support) and the quadrature cell d (at most a fifth of it). That is what lets a sparse grid,
// which holds phi only in its band (past it, +-background: `clip`), give the dense grid's map:
// within a cell diagonal of the band's edge its trilinear samples are clipped, so far is at
// most that, the band less a diagonal.
bool flatAround(uint c, vec3 q, float phi, vec3 n, float clip) {
    float step = 0.5 * uSupport;
    float tolerance = 0.01 * uSupport / float(kVolumeMapSteps);
    float far = min(0.6 * uSupport, clip - sqrt(3.0) * colliders[c].voxelSize);
    for (int k = -2; k <= 2; ++k)
        for (int j = -2; j <= 2; ++j)
            for (int i = -2; i <= 2; ++i) {
                vec3 o = vec3(i, j, k) * step;
                if (!(dot(o, o) < uSupport * uSupport))
                    continue;
                if (!inGridBox(c, q + o))
                    continue;
                float phiHere = sampleAround(c, q + o);
                float planeHere = phi + dot(n, o);
                bool beyondBand =
                    min(phiHere, planeHere) >= far || max(phiHere, planeHere) <= -far;
                if (!(abs(phiHere - planeHere) <= tolerance) && !beyondBand)
                    return false;
            }
    return true;
}

// phi at grid point p of collider c (inside its grid).
float colliderValueAt(uint c, ivec3 p) {
#ifdef SLUICE_SPARSE_COLLIDERS
    if (gSparse)
        return sparseValue(gAcc, p);
#endif
    return sdfAt(colliders[c].sdfOffset, colliders[c].dims, uvec3(p));
}

// The volume map at grid point p (local point q) whose phi is phi and unit normal n. The
// quadrature's cells are uStride grid cells wide when the grid is at least kVolumeMapSteps cells
// per support radius (its values read as they are), else support / kVolumeMapSteps (the field
// read trilinearly).
float volumeCorrection(uint c, uvec3 p, vec3 q, float phi, vec3 n) {
    float voxel = colliders[c].voxelSize;
    bool onGrid = uStride > 0u;
    float d = onGrid ? float(uStride) * voxel : uSupport / float(kVolumeMapSteps);
    int steps = int(uSupport / d);
    ivec3 dims = ivec3(colliders[c].dims);
    float weights = 0.0, solid = 0.0, plane = 0.0;
    for (int k = -steps; k <= steps; ++k)
        for (int j = -steps; j <= steps; ++j)
            for (int i = -steps; i <= steps; ++i) {
                vec3 o = vec3(i, j, k) * d;
                float a = 1.0 - dot(o, o) / (uSupport * uSupport);
                if (!(a > 0.0))
                    continue;
                float w = a * a * a;
                weights += w;
                float phiHere;
                if (onGrid) {
                    ivec3 at = ivec3(p) + ivec3(i, j, k) * int(uStride);
                    if (any(lessThan(at, ivec3(0))) || any(greaterThanEqual(at, dims)))
                        continue; // past the grid the field is only extrapolated: taken as flat
                    phiHere = colliderValueAt(c, at);
                } else {
                    if (!inGridBox(c, q + o))
                        continue;
                    phiHere = sampleAround(c, q + o);
                }
                solid += w * clamp(0.5 - phiHere / d, 0.0, 1.0);
                plane += w * clamp(0.5 - (phi + dot(n, o)) / d, 0.0, 1.0);
            }
    return (solid - plane) / weights;
}

void main() {
    uint c = uCollider;
    uvec3 dims = colliders[c].dims;
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uPoints)
        return;
    ivec3 at = ivec3(i % dims.x, (i / dims.x) % dims.y, i / (dims.x * dims.y));
    float clip = uintBitsToFloat(0x7f800000u); // infinite: a dense grid holds phi everywhere
#ifdef SLUICE_SPARSE_COLLIDERS
    if (colliders[c].gridKind == kColliderSparse) {
        // Point i is voxel i % 512 of leaf i / 512 (NanoVdbGlsl.h, sparseLeafSlot's order).
        at = sparseLeafVoxel(colliders[c].sdfOffset, i / 512u, i % 512u);
        clip = sparseBackground(colliders[c].sdfOffset);
        if (any(lessThan(at, ivec3(0))) || any(greaterThanEqual(at, ivec3(dims)))) {
            mapOut[colliders[c].volumeMap + i] = 0.0; // a leaf's voxel past the grid box
            return;
        }
    }
#endif
    uvec3 p = uvec3(at);
    vec3 q = colliders[c].origin + vec3(p) * colliders[c].voxelSize;
    // phi and its gradient at the point from the cell above it (below it on the last plane),
    // not from q's rounded grid coordinates: where the field has a kink (a concave edge's
    // diagonal) the two sides' gradients differ, and a map must not depend on the rounding.
    uvec3 cell = min(p, dims - 2u);
    float v[8];
    colliderCorners(c, cell, v);
    vec3 grad;
    float phi = trilinearCell(v, vec3(p - cell), grad);
    grad /= colliders[c].voxelSize;
    float len = length(grad);
    // On a ridge of the field (the diagonal of a concave edge) the gradient vanishes; the flat
    // share there is the same whichever way the plane faces, up to the quadrature's error.
    vec3 n = len > 0.0 ? grad / len : vec3(0.0, 1.0, 0.0);
    float more = 0.0;
    // A particle is kept outside the solid, so the trilinear reads that matter reach at most a
    // cell diagonal into it: deeper points keep 0.
    bool read = phi > -2.0 * colliders[c].voxelSize;
    if (read && phi < uSupport) {
#ifdef SLUICE_SPARSE_COLLIDERS
        gSparse = colliders[c].gridKind == kColliderSparse;
        if (gSparse)
            gAcc = sparseAccessor(colliders[c].sdfOffset);
#endif
        if (!flatAround(c, q, phi, n, clip))
            more = volumeCorrection(c, p, q, phi, n);
    }
    mapOut[colliders[c].volumeMap + i] = more;
}
