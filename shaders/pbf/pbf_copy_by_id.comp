// The particles in id order, into buffers the game owns (Simulation::copyParticlesById,
// docs/embedding.md, "Copies in id order"): each live particle whose id lies in
// [firstId, firstId + idCount) writes its position, and its velocity when asked, to entry
// id - firstId, with w = 1. The CPU clears the entries first, so an id no live particle holds
// reads w = 0. One invocation per slot in use.
#version 450 core

#include "shared/ChunkedDispatch.h"
#include "shared/Pbf.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindPosIn) readonly buffer Positions { vec4 pos[]; };
layout(std430, binding = kBindVelIn) readonly buffer Velocities { vec4 vel[]; };
layout(std430, binding = kBindIdIn) readonly buffer Ids { uint ids[]; };
layout(std430, binding = kBindPosOut) writeonly buffer PositionsOut { vec4 posOut[]; };
layout(std430, binding = kBindVelOut) writeonly buffer VelocitiesOut { vec4 velOut[]; };

uniform uint slots;          // slots in use
uniform uint firstId;        // the id of entry 0
uniform uint idCount;        // entries
uniform uint withVelocities; // 1: velOut is the game's velocity buffer

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= slots)
        return;
    vec4 p = pos[i];
    uint entry = ids[i] - firstId; // wraps past idCount for an id below firstId
    // A removed particle not yet compacted away is marked w = 1 (pbf_reorder.comp).
    if (p.w != 0.0 || entry >= idCount)
        return;
    posOut[entry] = vec4(p.xyz, 1.0);
    if (withVelocities != 0u)
        velOut[entry] = vec4(vel[i].xyz, 1.0);
}
