// The fluid's force on each measured collider that is no body (Simulation::measureForce), once
// per substep after the solve: what it pushed the particles by, summed in its slot of the body
// sums by pbf_delta.comp, is the impulse m sum(dx) / dt the water took from it; the collider takes
// the opposite, -m sum(dx) / dt^2 of force over the substep, and the moment's likewise about its
// origin. The slot is zeroed for the next substep. The step's mean goes into `forces`
// (docs/embedding.md, "Forces on colliders"). One invocation per collider.
#version 450 core

#define PBF_WITH_COLLIDERS 1
#include "glsl/PbfGlsl.h"

layout(local_size_x = 64) in;

layout(std430, binding = kBindBodySums) buffer BodySums { uint bodySums[]; };
layout(std430, binding = kBindColliderForces) buffer Forces { GpuColliderForce forces[]; };

#include "glsl/BodySumsGlsl.h"

// The first substep of a step starts the means again; each adds its share.
uniform uint firstSubstep;
uniform float substepShare;

void main() {
    uint c = gl_GlobalInvocationID.x;
    if (c >= P.colliderCount || colliders[c].body != kNoBody)
        return;
    uint slot = colliders[c].forceSlot;
    vec3 force = vec3(0.0), torque = vec3(0.0);
    if (slot != kNoBody) {
        float perDx = -P.particleMass * P.invDt * P.invDt;
        force = perDx * sumOf(slot, kBodySumPush) / (kSumUnitsPerH * P.invH);
        torque = perDx * sumOf(slot, kBodySumMoment) / solidMomentScale(c);
        // The push and moment sums, positive and negative parts, back to zero.
        for (uint w = kBodySumPush; w < kBodySumHeldPush; ++w)
            bodySums[slot * kBodySumWords + w] = 0u;
    }
    bool first = firstSubstep != 0u;
    forces[c].force = (first ? vec3(0.0) : forces[c].force) + substepShare * force;
    forces[c].torque = (first ? vec3(0.0) : forces[c].torque) + substepShare * torque;
}
