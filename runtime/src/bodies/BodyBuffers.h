// Private: the dynamic bodies' part of a Simulation's state (docs/bodies.md): their set-up,
// records, reaction sums and contact points on the GPU, the ones the game holds, and the
// snapshots latestBodies reads without waiting.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "bodies/BodySetup.h"
#include "render/GlObjects.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

struct BodyBuffers {
    BodySetup bodySetup;
    std::uint32_t bodyCount = 0;
    std::uint32_t removedAtSpawn = 0; // particles of the blocks that started inside a body
    std::optional<BodyDrag> drag;     // the viewer's mouse spring
    // GpuBody[], fixed-point sums, contact points, the body pass's state between its dispatches
    gpu::Buffer bodyBuf, bodySums, bodySamples, bodySteps;
    // A dynamic body the game holds (setBodyKinematic): where its asset frame is at the next
    // step's start, and where setColliderPose asked it to be at that step's end.
    struct KinematicBody {
        ColliderPose at;
        std::optional<ColliderPose> to;
    };
    std::vector<std::optional<KinematicBody>> kinematic; // per body
    // The bodies' records copied after each step, read back once their fence passes
    // (latestBodies); the oldest is overwritten, never waited for.
    struct BodySnapshot {
        gpu::Buffer records;
        Fence fence;
        std::uint64_t step = 0;
        double time = 0.0;
    };
    std::array<BodySnapshot, 3> bodySnapshots;
    std::size_t nextSnapshot = 0;
};

} // namespace sluice::rt
