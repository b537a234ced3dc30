// Private: the particles' part of a Simulation's state (Simulation::Impl is made of this and the
// other groups beside it): the live count, the ids, the ping-pong buffers the passes read and
// write, the emitters' schedule and the buffers a game draws or copies from.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/ParticleCopy.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/rt/sim/SceneSetup.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

struct ParticleBuffers {
    explicit ParticleBuffers(const format::Scene& scene) : emitters(scene) {}

    std::uint32_t capacity = 0;
    std::uint32_t count = 0;  // slots in use (live and, until trimmed, removed)
    std::uint32_t nextId = 0; // the id the next particle gets
    int cur = 0;              // which of pos/vel/id [2] holds the current particles
    bool capacityReached = false;
    bool emittersOn = true;
    EmitterSchedule emitters;
    // x, v and id (current and next, after the sort's reorder), x* (the solve's two, ping-pong
    // between iterations) and x* at the substep's start.
    gpu::Buffer pos[2], vel[2], id[2], pred[2], predStart;
    std::vector<ParticleState> staging; // uploads and downloads through the CPU
    IdOrderCopy idOrderCopy;            // copyParticlesById
    gpu::Buffer drawArgs;               // the view's DrawArraysIndirectCommand (updateDrawArgs)
};

} // namespace sluice::rt
