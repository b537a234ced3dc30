// sluice-play --headless: steps a scene without a window (EGL), printing the statistics table
// and writing statistics, PLY files and captured frames as asked.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "capture/CaptureFrames.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/rt/render/Renderer.h"
#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::rt {

/// The flags of a headless run (the output folders exist already: prepareRunOutputs).
struct HeadlessOptions {
    std::uint64_t steps = 1;        ///< steps to run, >= 1
    std::uint64_t statsEvery = 0;   ///< record statistics every K steps; 0: about 20 rows
    std::string statsJson;          ///< statistics file, empty for none
    std::string plyDir;             ///< PLY folder, empty for none
    std::string bodiesCsv;          ///< body trajectory table (BodiesCsv.h), empty for none
    std::string surfaceDir;         ///< surface mesh folder (surface_NNNNNN.ply), empty for none
    std::uint64_t surfaceEvery = 1; ///< a surface mesh every K steps
    SurfaceOptions surface;         ///< the meshes' options; particleRadius: the scene's
    std::uint64_t dumpEvery = 1;    ///< a PLY file every K steps
    bool deterministic = false;
    std::uint32_t neighbourLanes = 0; ///< SimulationOptions::neighbourLanes
    bool check = false; ///< exit 1 when a particle went non-finite or ended inside a collider,
                        ///< or a body was put back (StepStats::bodyFaults)
    bool quiet = false;
    CaptureOptions capture;          ///< --frames, --video, --screenshot-at
    glm::uvec2 imageSize{1280, 720}; ///< capture size [pixels]
    RenderSettings render;
};

/// Runs `scene` with its loaded `colliders` (one per scene collider) for options.steps steps;
/// returns a sluice-play exit code (PlayCli.h).
int playHeadless(const HeadlessOptions& options, const format::Scene& scene,
                 std::vector<format::ColliderAsset> colliders);

} // namespace sluice::rt
