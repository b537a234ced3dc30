// Statistics of a recorded step: maximum speed and particles inside colliders
// (phi < -0.5 r for some collider). Integer atomics, so the counts are exact and order-free.
#version 450 core

#define PBF_WITH_COLLIDERS 1
#define PBF_WITH_BODIES 1
#include "glsl/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindPosIn) readonly buffer PosIn { vec4 pos[]; };
layout(std430, binding = kBindVelIn) readonly buffer VelIn { vec4 vel[]; };
layout(std430, binding = kBindStats) buffer Stats { PbfStats stats; };

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    // A removed particle not yet compacted away is marked w = 1 (pbf_reorder.comp).
    if (i >= PBF_COUNT || pos[i].w != 0.0)
        return;
    vec3 x = pos[i].xyz;
    float speed = length(vel[i].xyz);
    if (!isnan(speed))
        atomicMax(stats.maxSpeedBits, floatBitsToUint(speed));
    for (uint c = 0u; c < P.colliderCount; ++c) {
        // A body whose bounding sphere is out of reach has phi > 0 here: skip its samples.
        if (colliders[c].body != kNoBody && bodyOutOfReach(c, x, 0.0))
            continue;
        vec3 normal;
        if (colliderDistance(c, x, normal) < -0.5 * PBF_RADIUS) {
            atomicAdd(stats.insideColliders, 1u);
            break;
        }
    }
}
