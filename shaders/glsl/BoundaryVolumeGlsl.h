// Walls and static colliders as boundary volume in the density (docs/pbf.md, "Boundary volume"
// and "Volume maps"): the lambda and delta passes, the volume map pass and the boundary probe.
// Include after glsl/PbfGlsl.h with PBF_WITH_COLLIDERS defined.
#ifndef SLUICE_BOUNDARY_VOLUME_GLSL_H
#define SLUICE_BOUNDARY_VOLUME_GLSL_H

// The domain's walls as boundary volume (docs/pbf.md, "Boundary volume"): each face is a flat
// boundary r beyond the plane the particles' centres are clamped to, so a particle resting
// against it (at r) sees the calibrated share. The two faces of an axis cover disjoint parts of
// the support and add; the axes combine as independent cuts, 1 - (1 - f_x)(1 - f_y)(1 - f_z),
// which is within 1.3 % of the exact share in an edge or a corner. Adds the walls' share to
// `boundary` and its gradient (outward from the fluid, into the walls) to `gradient`.
void addWallBoundary(vec3 x, inout float boundary, inout vec3 gradient) {
    if (P.hasDomain == 0u)
        return;
    vec3 below = x - P.domainMin + PBF_RADIUS; // to the faces at the low ends of x, y and z
    vec3 above = P.domainMax - x + PBF_RADIUS; // and at the high ends
    if (all(greaterThanEqual(min(below, above), vec3(PBF_H))))
        return;
    vec3 open = vec3(1.0); // per axis, the share of the support in front of both faces
    vec3 slope = vec3(0.0); // and its derivative along the axis
    float k = P.boundaryScale;
    for (int a = 0; a < 3; ++a) {
        if (below[a] < PBF_H) {
            open[a] -= boundaryShare(below[a]) / k;
            slope[a] -= boundaryShareSlope(below[a]) / k;
        }
        if (above[a] < PBF_H) {
            open[a] -= boundaryShare(above[a]) / k;
            slope[a] += boundaryShareSlope(above[a]) / k;
        }
    }
    boundary += k * (1.0 - open.x * open.y * open.z);
    gradient -= k * slope * vec3(open.y * open.z, open.x * open.z, open.x * open.y);
}

// The eight values of collider c's volume map (from word `base`) in the cell with lower corner
// b, as v[x + 2y + 4z]: one per grid point of a dense grid; one per voxel of each leaf of a
// sparse one, in the tree's leaf order, 0 where a point is in no leaf (a tile: deep inside, or
// farther out than the band, where the map holds nothing).
void volumeMapCorners(uint c, uint base, uvec3 b, out float v[8]) {
#ifdef SLUICE_SPARSE_COLLIDERS
    if (colliders[c].gridKind == kColliderSparse) {
        uint grid = colliders[c].sdfOffset;
        pnanovdb_readaccessor_t acc = sparseAccessor(grid);
        uint firstLeaf = sparseLeaf(grid, 0u).address.byte_offset;
        for (int k = 0; k < 8; ++k) {
            uint slot;
            bool stored = sparseLeafSlot(
                acc, firstLeaf, ivec3(b) + ivec3(k & 1, (k >> 1) & 1, k >> 2), slot);
            v[k] = stored ? uintBitsToFloat(sdfWords[base + slot]) : 0.0;
        }
        return;
    }
#endif
    denseCorners(base, colliders[c].dims, b, v);
}

// What collider c's volume map adds at local point q (docs/pbf.md, "Volume maps"): the share of
// the support the collider's solid really fills less the share of the flat boundary at q's phi,
// trilinear on the collider's grid, 0 outside its grid box and for a collider without a map.
// `grad` gets its gradient in local units [1 / asset unit].
float colliderVolumeCorrection(uint c, vec3 q, out vec3 grad) {
    grad = vec3(0.0);
    uint base = colliders[c].volumeMap;
    vec3 lo = colliders[c].origin;
    if (base == kNoVolumeMap || any(lessThan(q, lo)) || any(greaterThan(q, colliders[c].boxMax)))
        return 0.0;
    float voxel = colliders[c].voxelSize;
    uvec3 dims = colliders[c].dims;
    vec3 g = (q - lo) / voxel;
    vec3 cellLo = clamp(floor(g), vec3(0.0), vec3(dims) - 2.0);
    vec3 t = clamp(g - cellLo, 0.0, 1.0);
    float v[8];
    volumeMapCorners(c, base, uvec3(cellLo), v);
    float value = trilinearCell(v, t, grad);
    grad /= voxel;
    return value;
}

// Static or kinematic collider c as boundary volume at x (docs/pbf.md, "Boundary volume"): the
// share of a flat boundary at the collider's phi, from the surface the push-out keeps centres
// r away from, so a particle resting on it sees the calibrated share, plus what the collider's
// volume map adds at edges, corners and thin walls ("Volume maps"), and the share's gradient.
// False where c holds no share of x's support.
bool colliderBoundaryAt(uint c, vec3 x, out float share, out vec3 slope) {
    vec3 q = colliderLocal(c, x);
    vec3 normal;
    float phi = colliderDistanceAt(c, q, normal);
    float len = length(normal);
    bool mapped = colliders[c].volumeMap != kNoVolumeMap;
    share = 0.0;
    slope = vec3(0.0);
    // Without a gradient (the ridge of a concave edge's field, a sparse grid's inside tile)
    // only a collider's map, outside it, says where the solid lies.
    if (!(phi < PBF_H) || !(len > 0.0 || (mapped && phi >= 0.0)))
        return false;
    share = boundaryShare(phi);
    slope = len > 0.0 ? boundaryShareSlope(phi) * (normal / len) : vec3(0.0);
    if (mapped) {
        // The share's own gradient: the field's gradient, shorter than 1 near an edge, as
        // the map's values were taken against (pbf_volume_map.comp).
        slope = boundaryShareSlope(phi) * normal;
        vec3 mapGrad;
        float more = colliderVolumeCorrection(c, q, mapGrad);
        share += P.boundaryScale * more;
        // R g / s, as (R^T / s)^T g.
        slope += P.boundaryScale * (transpose(mat3(colliders[c].worldToGrid)) * mapGrad);
        if (!(share > 0.0))
            return false;
    }
    return true;
}

// Every static and kinematic collider's share at x (colliderBoundaryAt) added to `boundary`,
// its gradient to `gradient`. Dynamic bodies are summed per body by the passes.
void addColliderBoundary(vec3 x, inout float boundary, inout vec3 gradient) {
    uint mask = P.staticColliders, c = 0u;
    while (nextStaticCollider(mask, c)) {
        float share;
        vec3 slope;
        if (!colliderBoundaryAt(c, x, share, slope))
            continue;
        boundary += share;
        gradient += slope;
    }
}

#endif // SLUICE_BOUNDARY_VOLUME_GLSL_H
