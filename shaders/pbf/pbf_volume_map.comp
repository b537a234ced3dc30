// Builds a static collider's volume map (docs/pbf.md, "Volume maps"): at each grid point q of
// collider uCollider, the share of a poly6 support of radius uSupport the collider's solid fills,
// less the share of the flat boundary at q's phi along its normal. The solver adds it to the
// flat closed form (BoundaryVolumeGlsl.h), which is exact on flat faces only; this makes edges,
// corners and thin walls right. Both shares are the same quadrature (kVolumeMapSteps points per
// support radius each way, a cell's volume fraction from phi at its centre), so its error on
// flat faces cancels; points farther than uSupport from the surface get 0. One invocation per
// grid point; run once when a scene loads and again when h changes.
#version 450 core

#define PBF_WITH_COLLIDERS 1
#include "shared/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

// The SDF buffer again: the map's words lie past every grid's samples (GpuCollider::volumeMap).
layout(std430, binding = kBindVolumeMapOut) writeonly buffer MapOut { float mapOut[]; };

uniform uint uCollider;
uniform float uSupport; // h in the collider's local units [asset units]

// The volume map at local point q whose phi is phi and unit normal n.
float volumeCorrection(uint c, vec3 q, float phi, vec3 n) {
    const int steps = int(kVolumeMapSteps);
    float d = uSupport / float(steps);
    float weights = 0.0, solid = 0.0, plane = 0.0;
    for (int k = -steps; k <= steps; ++k)
        for (int j = -steps; j <= steps; ++j)
            for (int i = -steps; i <= steps; ++i) {
                vec3 o = vec3(i, j, k) * d;
                float a = 1.0 - dot(o, o) / (uSupport * uSupport);
                if (!(a > 0.0))
                    continue;
                float w = a * a * a;
                float phiHere;
                vec3 unused;
                sampleCollider(c, q + o, phiHere, unused);
                weights += w;
                solid += w * clamp(0.5 - phiHere / d, 0.0, 1.0);
                plane += w * clamp(0.5 - (phi + dot(n, o)) / d, 0.0, 1.0);
            }
    return (solid - plane) / weights;
}

void main() {
    uint c = uCollider;
    uvec3 dims = colliders[c].dims;
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= dims.x * dims.y * dims.z)
        return;
    uvec3 p = uvec3(i % dims.x, (i / dims.x) % dims.y, i / (dims.x * dims.y));
    vec3 q = colliders[c].origin + vec3(p) * colliders[c].voxelSize;
    float phi;
    vec3 grad;
    sampleCollider(c, q, phi, grad);
    float len = length(grad);
    // On a ridge of the field (the diagonal of a concave edge) the gradient vanishes; the flat
    // share there is the same whichever way the plane faces, up to the quadrature's error.
    vec3 n = len > 0.0 ? grad / len : vec3(0.0, 1.0, 0.0);
    float more = 0.0;
    if (abs(phi) < uSupport)
        more = volumeCorrection(c, q, phi, n);
    mapOut[colliders[c].volumeMap + i] = more;
}
