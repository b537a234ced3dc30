// Per stored block: each sample writes one vertex per crossing edge, at the linear
// interpolation of the iso value along it, with the normal down the field's gradient (central
// differences at both ends, interpolated), at its block's base plus a scan over the block's
// rows, in a fixed order; and keeps its first vertex for the triangle pass. One invocation
// per row of samples counts and numbers; then the block's samples that own a crossing edge,
// listed in shared memory, are shared out one per invocation (a row has few of them, and
// software GL runs neighbouring rows side by side in one vector).
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

// The samples owning a crossing edge, in sample order: the sample's index in the block (bits
// 0-8), its edges along +x, +y, +z (bits 9-11) and its first vertex in the block (from 12).
shared uint owners[kSurfaceBlockSamples];

// Central differences of the field at `local` in the loaded tile (unscaled: only its direction
// is used).
vec3 gradient(ivec3 l) {
    return vec3(float(tileValue(l + ivec3(1, 0, 0))) - float(tileValue(l - ivec3(1, 0, 0))),
                float(tileValue(l + ivec3(0, 1, 0))) - float(tileValue(l - ivec3(0, 1, 0))),
                float(tileValue(l + ivec3(0, 0, 1))) - float(tileValue(l - ivec3(0, 0, 1))));
}

// The crossing edges along +x, +y and +z of a sample code (its bits 0, 1 and 3) as bits 0-2.
uint axisEdges(uint code) {
    return (code & 3u) | ((code >> 1u) & 4u);
}

// The vertices of the sample at `local` in the block at `origin`, from `first` on: one per
// crossing edge along +x, +y, +z, in that order.
void writeVertices(ivec3 origin, ivec3 local, uint edges, uint first) {
    float iso = float(uIsoFixed) + 0.5;
    ivec3 s = origin + local;
    float fa = float(tileValue(local));
    vec3 ga = gradient(local);
    uint at = first;
    for (uint axis = 0u; axis < 3u; ++axis) {
        if ((edges & (1u << axis)) == 0u)
            continue;
        ivec3 step = cornerOffset(1u << axis);
        ivec3 n = local + step;
        float fb = float(tileValue(n));
        float t = clamp((iso - fa) / (fb - fa), 0.0, 1.0);
        vec3 g = mix(ga, gradient(n), t);
        float len = length(g);
        vec3 p = uOrigin + (vec3(s) + t * vec3(step)) * uCell;
        vec3 normal = len > 0.0 ? -g / len : vec3(0.0, 1.0, 0.0);
        for (uint k = 0u; k < 3u; ++k) {
            positions[3u * at + k] = p[k];
            normals[3u * at + k] = normal[k];
        }
        ++at;
    }
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
    // The row's owners (low 16 bits) and vertices (high 16 bits), numbered over the rows in
    // one scan: at most 512 and 1536 a block.
    uint owned = 0u;
    uint mine = 0u;
    for (uint x = 0u; x < kSurfaceBlockSide; ++x) {
        uint edges = bitCount(sampleCode[first + x] & 0x7fu);
        owned += edges != 0u ? 1u : 0u;
        mine += edges;
    }
    uint total;
    uint before = rowExclusiveScan(row, owned | (mine << 16u), total);
    uint owner = before & 0xffffu;
    uint vertex = before >> 16u;
    uint base = vertBase[slot];
    for (uint x = 0u; x < kSurfaceBlockSide; ++x) {
        uint edges = axisEdges(sampleCode[first + x]);
        sampleVert[first + x] = base + vertex;
        if (edges == 0u)
            continue;
        owners[owner++] = (row * kSurfaceBlockSide + x) | (edges << 9u) | (vertex << 12u);
        vertex += uint(bitCount(edges));
    }
    barrier();
    for (uint i = row; i < (total & 0xffffu); i += kSurfaceBlockRows) {
        uint entry = owners[i];
        writeVertices(origin, laneCoord(entry & 511u), (entry >> 9u) & 7u,
                      base + (entry >> 12u));
    }
}
