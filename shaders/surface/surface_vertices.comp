// Per stored block: each sample writes one vertex per crossing edge, at the linear
// interpolation of the iso value along it, with the normal down the field's gradient (central
// differences at both ends, interpolated), at its block's base plus a scan over the block's
// rows, in a fixed order; and keeps its first vertex for the triangle pass. One invocation
// per row of samples counts and numbers; then the block's vertices, listed in shared memory,
// are shared out one per invocation (a row has few of them, and software GL runs neighbouring
// rows side by side in one vector), each reading the field through the blocks round it.
#version 450 core

#include "glsl/SurfaceGlsl.h"

layout(local_size_x = kSurfaceBlockRows) in;

layout(std430, binding = kSurfBindBlockVerts) readonly buffer BlockVerts { uint blockVerts[]; };
layout(std430, binding = kSurfBindVertBase) readonly buffer VertBase { uint vertBase[]; };
layout(std430, binding = kSurfBindSampleVert) writeonly buffer SampleVert { uint sampleVert[]; };
layout(std430, binding = kSurfBindSampleCode) readonly buffer SampleCode { uint sampleCode[]; };
// Packed float triples, the layout of the CPU's vectors: read back with one copy each.
layout(std430, binding = kSurfBindPositions) writeonly buffer Positions { float positions[]; };
layout(std430, binding = kSurfBindNormals) writeonly buffer Normals { float normals[]; };

// The first samples of the 27 blocks round this one (storedBlockBase), block offset
// (dx, dy, dz) at 13 + dx + 3 dy + 9 dz.
shared uint nearBase[27];
ivec3 gOrigin; // the block's first sample in the grid

// The field at local sample l (each coordinate in -1 .. 8), 0 where it is not stored.
float fieldAt(ivec3 l) {
    ivec3 s = gOrigin + l;
    if (any(lessThan(s, ivec3(0))) || any(greaterThanEqual(s, uSamples)))
        return 0.0;
    int side = int(kSurfaceBlockSide);
    ivec3 d = ivec3(blockStep(l.x), blockStep(l.y), blockStep(l.z));
    uint base = nearBase[13 + d.x + 3 * d.y + 9 * d.z];
    return base == 0xffffffffu ? 0.0 : float(field[base + laneOf(l - side * d)]);
}

// Central differences of the field at local sample l (unscaled: only its direction is used).
vec3 gradient(ivec3 l) {
    return vec3(fieldAt(l + ivec3(1, 0, 0)) - fieldAt(l - ivec3(1, 0, 0)),
                fieldAt(l + ivec3(0, 1, 0)) - fieldAt(l - ivec3(0, 1, 0)),
                fieldAt(l + ivec3(0, 0, 1)) - fieldAt(l - ivec3(0, 0, 1)));
}

// The crossing edges along +x, +y and +z of a sample code (its bits 0, 1 and 3) as bits 0-2.
uint axisEdges(uint code) {
    return (code & 3u) | ((code >> 1u) & 4u);
}

// The vertex on the crossing edge from local sample `local` along `axis` (0, 1, 2: +x, +y, +z),
// written at `at`.
void writeVertex(ivec3 local, uint axis, uint at) {
    float iso = float(uIsoFixed) + 0.5;
    ivec3 step = cornerOffset(1u << axis);
    ivec3 n = local + step;
    float fa = fieldAt(local);
    float fb = fieldAt(n);
    float t = clamp((iso - fa) / (fb - fa), 0.0, 1.0);
    vec3 g = mix(gradient(local), gradient(n), t);
    float len = length(g);
    vec3 p = uOrigin + (vec3(gOrigin + local) + t * vec3(step)) * uCell;
    vec3 normal = len > 0.0 ? -g / len : vec3(0.0, 1.0, 0.0);
    for (uint k = 0u; k < 3u; ++k) {
        positions[3u * at + k] = p[k];
        normals[3u * at + k] = normal[k];
    }
}

// The block's vertices in order: the sample's index in the block (bits 0-8) and the axis of
// its crossing edge (bits 9-10). At most three a sample.
shared uint vertexEdges[3u * kSurfaceBlockSamples];

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockRows;
    uint row = gl_LocalInvocationID.x;
    // Blocks without a vertex (inside the water or outside it) have nothing to do: the whole
    // group leaves (their samples own no crossing edge, so nothing reads their entries).
    if (slot >= uCount || blockVerts[slot] == 0u)
        return;
    ivec3 block = blockCoord(activeBlock[slot]);
    gOrigin = block * int(kSurfaceBlockSide);
    if (row < 27u) // published by the scan's barrier
        nearBase[row] = storedBlockBase(block + ivec3(int(row % 3u), int((row / 3u) % 3u),
                                                      int(row / 9u)) - 1);
    uint first = slot * kSurfaceBlockSamples + row * kSurfaceBlockSide;
    // The row's vertices, numbered over the rows in one scan, then listed one entry each.
    uint edges[kSurfaceBlockSide];
    uint mine = 0u;
    for (uint x = 0u; x < kSurfaceBlockSide; ++x) {
        edges[x] = axisEdges(sampleCode[first + x]);
        mine += uint(bitCount(edges[x]));
    }
    uint total;
    uint vertex = rowExclusiveScan(row, mine, total);
    uint base = vertBase[slot];
    for (uint x = 0u; x < kSurfaceBlockSide; ++x) {
        sampleVert[first + x] = base + vertex;
        for (uint axis = 0u; axis < 3u; ++axis)
            if ((edges[x] & (1u << axis)) != 0u)
                vertexEdges[vertex++] = (row * kSurfaceBlockSide + x) | (axis << 9u);
    }
    barrier();
    for (uint i = row; i < total; i += kSurfaceBlockRows) {
        uint entry = vertexEdges[i];
        writeVertex(laneCoord(entry & 511u), entry >> 9u, base + i);
    }
}
