// Per stored block: each sample writes one vertex per crossing edge, at the linear
// interpolation of the iso value along it, with the normal down the field's gradient (central
// differences at both ends, interpolated), at its block's base plus a scan over the block's
// rows, in a fixed order; and keeps its first vertex for the triangle pass. One invocation
// per row of samples.
#version 450 core

#include "shared/SurfaceGlsl.h"

layout(local_size_x = kSurfaceBlockRows) in;

layout(std430, binding = kSurfBindBlockVerts) readonly buffer BlockVerts { uint blockVerts[]; };
layout(std430, binding = kSurfBindVertBase) readonly buffer VertBase { uint vertBase[]; };
layout(std430, binding = kSurfBindSampleVert) writeonly buffer SampleVert { uint sampleVert[]; };
layout(std430, binding = kSurfBindSampleCode) readonly buffer SampleCode { uint sampleCode[]; };
// Packed float triples, the layout of the CPU's vectors: read back with one copy each.
layout(std430, binding = kSurfBindPositions) writeonly buffer Positions { float positions[]; };
layout(std430, binding = kSurfBindNormals) writeonly buffer Normals { float normals[]; };

// Central differences of the field at `local` in the loaded tile (unscaled: only its direction
// is used).
vec3 gradient(ivec3 l) {
    return vec3(float(tileValue(l + ivec3(1, 0, 0))) - float(tileValue(l - ivec3(1, 0, 0))),
                float(tileValue(l + ivec3(0, 1, 0))) - float(tileValue(l - ivec3(0, 1, 0))),
                float(tileValue(l + ivec3(0, 0, 1))) - float(tileValue(l - ivec3(0, 0, 1))));
}

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockRows;
    uint row = gl_LocalInvocationID.x;
    // Blocks without a vertex (inside the water or outside it) have nothing to do: the whole
    // group leaves (their samples own no crossing edge, so nothing reads their entries).
    if (slot >= uCount || blockVerts[slot] == 0u)
        return;
    ivec3 origin = blockCoord(activeBlock[slot]) * int(kSurfaceBlockSide);
    loadTile(origin, row);
    uint first = slot * kSurfaceBlockSamples + row * kSurfaceBlockSide;
    uint mine = 0u;
    for (uint x = 0u; x < kSurfaceBlockSide; ++x)
        mine += bitCount(sampleCode[first + x] & 0x7fu);
    uint total;
    uint base = vertBase[slot] + rowExclusiveScan(row, mine, total);
    float iso = float(uIsoFixed) + 0.5;
    for (uint x = 0u; x < kSurfaceBlockSide; ++x) {
        uint edges = sampleCode[first + x] & 0x7fu;
        sampleVert[first + x] = base;
        if (edges == 0u)
            continue;
        ivec3 local = laneCoord(row * kSurfaceBlockSide + x);
        ivec3 s = origin + local;
        float fa = float(tileValue(local));
        vec3 ga = gradient(local);
        for (uint d = 1u; d < 8u; ++d) {
            if ((edges & (1u << (d - 1u))) == 0u)
                continue;
            ivec3 n = local + cornerOffset(d);
            float fb = float(tileValue(n));
            float t = clamp((iso - fa) / (fb - fa), 0.0, 1.0);
            vec3 g = mix(ga, gradient(n), t);
            float len = length(g);
            vec3 p = uOrigin + (vec3(s) + t * vec3(cornerOffset(d))) * uCell;
            vec3 normal = len > 0.0 ? -g / len : vec3(0.0, 1.0, 0.0);
            for (uint k = 0u; k < 3u; ++k) {
                positions[3u * base + k] = p[k];
                normals[3u * base + k] = normal[k];
            }
            ++base;
        }
    }
}
