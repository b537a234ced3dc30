// Private: the removal's part of a Simulation's state (docs/embedding.md, "Removing particles").
// The predict pass sends the removed particles to the bucket after the last, the sort puts them
// after the live ones, and the CPU's count drops them once a fenced copy of the live count says
// how many there are.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "render/GlObjects.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/gpu/Buffer.h"

namespace sluice::rt {

struct ParticleRemoval {
    explicit ParticleRemoval(const format::Scene& scene)
        : drains(scene.drains), removal(!scene.drains.empty()) {}

    std::vector<format::Drain> drains;       // the scene's, or setDrains'
    std::vector<format::Drain> removeBoxes;  // removeParticlesIn's, for the next substep only
    std::vector<std::uint32_t> removeIdList; // removeParticles', ascending, next substep only
    bool removal = false;                    // some particle may have been removed (then for good)
    gpu::Buffer removeIdBuf;
    struct LiveRecord {
        gpu::Buffer word; // cellStart at the removed bucket: the live count after a step
        Fence fence;
        std::uint64_t step = 0;
        std::uint32_t count = 0; // slots in use then
    };
    std::array<LiveRecord, 3> liveRecords;
    std::size_t nextLive = 0;
    std::uint64_t lastTrim = 0;      // the step at whose end the count last dropped
    std::uint32_t removedBucket = 0; // the removed particles' bucket in the last sort
    bool sortedWithRemoval = false;  // the last sort had it: cellStart there is the live count
};

} // namespace sluice::rt
