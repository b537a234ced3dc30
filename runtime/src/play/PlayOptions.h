// The options of sluice-play's command line, and the checks made on them before a run: options
// that do nothing in the chosen mode or without another, a screenshot after the last step, a
// body table without bodies, surface options against the scene (PlayCli.cpp uses them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "capture/CaptureFrames.h"
#include "play/SceneChecks.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/format/support/Result.h"
#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::rt {

struct PlayOptions {
    std::string scene;
    bool headless = false;
    std::uint64_t steps = 0;
    std::uint64_t statsEvery = 0; // 0: about 20 rows over the run
    std::string statsJson;
    std::string plyDir;
    std::string bodiesCsv;
    std::string surfaceDir;
    std::uint64_t surfaceEvery = 1;
    float surfaceCell = 0.0f;
    float surfaceIso = 0.0f;
    bool surfaceAnisotropic = false;
    std::string surfaceKernel = "gaussian";
    std::optional<bool> surfaceNormalised; ///< unset: SurfaceOptions' default
    std::uint64_t dumpEvery = 1;
    bool deterministic = false;
    std::uint32_t neighbourLanes = 0; // 0: chosen for the renderer and the scene
    bool rasterSpheres = false;
    bool noDomainBox = false;
    bool check = false;
    bool quiet = false;
    bool strict = false;
    bool bench = false;
    std::string benchJson;
    std::uint64_t warmup = 20;
    std::uint32_t benchFrames = 0;
    // Rendering and capture (headless and window).
    CaptureOptions capture;
    std::string size; // empty: 1280x720, or 1920x1080 for --bench-frames
    std::string colour = "water";
    std::string surface = "spheres";
    // Window only.
    std::uint64_t maxFrames = 0;
    bool noVsync = false;
    bool noPanel = false;
    bool screenshotPanel = false;
    std::uint32_t stepsPerFrame = 1;
};

/// The three ways sluice-play runs.
enum class PlayMode { Headless, Window, Bench };

/// Options given that do nothing in `mode`, or nothing without another option.
void checkOptionUse(const CLI::App& app, const PlayOptions& o, PlayMode mode,
                    std::vector<PlayWarning>& out);

/// --bodies-csv for a scene without dynamic bodies would write only the header.
void checkBodiesCsv(const CLI::App& app, const format::Scene& scene, PlayMode mode,
                    std::vector<PlayWarning>& out);

/// The surface mesh options the command line asks for (--surface-cell, -iso, -kernel,
/// -normalised, -anisotropic); particleRadius is left 0, the scene's to set.
SurfaceOptions surfaceOptions(const PlayOptions& o);

/// --surface-cell and --surface-iso against the scene's particle radius, before anything runs.
Result<void> checkSurfaceOptions(const PlayOptions& o, const format::Scene& scene);

/// A --screenshot-at step the run never reaches.
void checkScreenshotStep(const PlayOptions& o, PlayMode mode, std::vector<PlayWarning>& out);

} // namespace sluice::rt
