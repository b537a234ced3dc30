// Private: the colliders' part of a Simulation's state: the assets, their records and grids in
// the SDF buffer, the volume maps, the poses a program sets, and the measured forces.
#pragma once

#include <optional>
#include <vector>

#include "colliders/ColliderForces.h"
#include "shared/Pbf.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/BufferTexture.h"
#include "sluice/gpu/Program.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

struct ColliderState {
    explicit ColliderState(std::size_t colliders) : driven(colliders) {}

    std::vector<format::ColliderAsset> colliderAssets;
    std::vector<shared::GpuCollider> colliderRecords;
    gpu::Buffer colliderBuf, sdfBuf;
    // The SDF buffer's texel view, which the passes fetch dense grids and volume maps through
    // (PbfGlsl.h, sdfAt); empty when sdfAsTexels is false and they read the storage block.
    gpu::BufferTexture sdfTexels;
    bool sdfAsTexels = true; // set by compilePasses: every grid and map fits a texel view
    gpu::Program volumeMapPass, boundaryProbe; // compiled when first needed (VolumeMaps.cpp)
    float volumeMapsH = 0.0f;    // the kernel radius the volume maps were built for [m]
    VolumeMapLoad volumeMapLoad; // what buildVolumeMaps last did
    bool volumeMapsFit = true;   // false: they would not fit in the SDF buffer's storage block
    // A pose a program set (setColliderPose): the collider moves from `from` at t0 to `to` at t1.
    struct DrivenPose {
        ColliderPose from;
        float t0 = 0.0f;
        ColliderPose to;
        float t1 = 0.0f;
    };
    std::vector<std::optional<DrivenPose>> driven; // per scene collider
    ColliderForceMeter forceMeter; // forces on static and kinematic colliders (measureForce)
};

} // namespace sluice::rt
