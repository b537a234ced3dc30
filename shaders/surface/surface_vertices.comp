// Per stored block: each sample writes one vertex per crossing edge, at the linear
// interpolation of the iso value along it, with the normal down the field's gradient (central
// differences at both ends, interpolated), at its block's base plus a work-group scan, in a
// fixed order; and keeps its first vertex and its crossing edges for the triangle pass.
#version 450 core

#include "shared/SurfaceGlsl.h"

layout(local_size_x = kSurfaceBlockSamples) in;

layout(std430, binding = kSurfBindVertBase) readonly buffer VertBase { uint vertBase[]; };
layout(std430, binding = kSurfBindSampleVert) writeonly buffer SampleVert { uint sampleVert[]; };
layout(std430, binding = kSurfBindSampleEdges) writeonly buffer SampleEdges { uint sampleEdges[]; };
layout(std430, binding = kSurfBindVertices) writeonly buffer Vertices { SurfaceVertex vertices[]; };

vec3 gradient(ivec3 s) {
    return vec3(float(sampleValue(s + ivec3(1, 0, 0))) - float(sampleValue(s - ivec3(1, 0, 0))),
                float(sampleValue(s + ivec3(0, 1, 0))) - float(sampleValue(s - ivec3(0, 1, 0))),
                float(sampleValue(s + ivec3(0, 0, 1))) - float(sampleValue(s - ivec3(0, 0, 1))));
}

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockSamples;
    uint lane = gl_LocalInvocationID.x;
    bool live = slot < uCount;
    ivec3 s = ivec3(0);
    uint edges = 0u;
    if (live) {
        s = blockCoord(activeBlock[slot]) * int(kSurfaceBlockSide) + laneCoord(lane);
        if (all(lessThan(s, uSamples)))
            edges = crossingEdges(s);
    }
    uint total;
    uint first = groupExclusiveScan(lane, bitCount(edges), total);
    if (!live)
        return;
    uint base = vertBase[slot] + first;
    sampleVert[slot * kSurfaceBlockSamples + lane] = base;
    sampleEdges[slot * kSurfaceBlockSamples + lane] = edges;
    if (edges == 0u)
        return;
    float iso = float(uIsoFixed) + 0.5;
    float fa = float(sampleValue(s));
    vec3 ga = gradient(s);
    uint k = 0u;
    for (uint d = 1u; d < 8u; ++d) {
        if ((edges & (1u << (d - 1u))) == 0u)
            continue;
        ivec3 n = s + cornerOffset(d);
        float fb = float(sampleValue(n));
        float t = clamp((iso - fa) / (fb - fa), 0.0, 1.0);
        vec3 g = mix(ga, gradient(n), t);
        float len = length(g);
        SurfaceVertex v;
        v.position = vec4(uOrigin + (vec3(s) + t * vec3(cornerOffset(d))) * uCell, 1.0);
        v.normal = vec4(len > 0.0 ? -g / len : vec3(0.0, 1.0, 0.0), 0.0);
        vertices[base + k] = v;
        ++k;
    }
}
