// sluice-play --bench: steady-state step and pass timings of a scene, as a table and JSON.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {

struct BenchOptions {
    std::uint64_t steps = 100;  ///< measured steps
    std::uint64_t warmup = 20;  ///< steps run first and not measured
    std::string json;           ///< results file, empty for none
    bool deterministic = false;
    std::uint32_t neighbourLanes = 0; ///< SimulationOptions::neighbourLanes
    /// After the steps: frames of the final state rendered and GPU-timed one at a time (0:
    /// none), at `renderSize` pixels, drawn with `render`, the scene camera's distance times
    /// `zoom`.
    std::uint32_t renderFrames = 0;
    glm::uvec2 renderSize{1920, 1080};
    RenderSettings render;
    float zoom = 1.0f;
};

/// Runs the benchmark on `scene` with its loaded `colliders` (one per scene collider) and
/// prints its table; returns a sluice-play exit code (PlayCli.h).
int runBench(const BenchOptions& options, const format::Scene& scene,
             std::vector<format::ColliderAsset> colliders);

} // namespace sluice::rt
