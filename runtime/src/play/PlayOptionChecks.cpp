// The checks on sluice-play's options before a run (PlayOptions.h).
#include "play/PlayOptions.h"

#include "sluice/rt/render/Renderer.h"
#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::rt {
namespace {

const char* modeWords(PlayMode mode) {
    switch (mode) {
    case PlayMode::Headless:
        return "in a --headless run";
    case PlayMode::Window:
        return "in the window";
    case PlayMode::Bench:
        return "with --bench";
    }
    return "";
}

/// An option and the modes it does something in.
struct OptionUse {
    const char* name;
    bool headless;
    bool window;
    bool bench;
};

constexpr OptionUse kOptionUses[] = {
    {"--steps", true, false, true},
    {"--stats-every", true, false, false},
    {"--stats-json", true, false, false},
    {"--dump-ply", true, false, false},
    {"--dump-every", true, false, false},
    {"--bodies-csv", true, false, false},
    {"--surface-mesh", true, false, false},
    {"--surface-every", true, false, false},
    {"--surface-cell", true, true, true},
    {"--surface-iso", true, true, true},
    {"--surface-kernel", true, true, true},
    {"--surface-normalised", true, true, true},
    {"--surface-anisotropic", true, true, true},
    {"--check", true, false, false},
    {"--quiet", true, true, false},
    {"--warmup", false, false, true},
    {"--bench-json", false, false, true},
    {"--frames", true, true, false},
    {"--every", true, true, false},
    {"--video", true, true, false},
    {"--fps", true, true, false},
    {"--screenshot-at", true, true, false},
    {"--shots", true, true, false},
    {"--max-frames", false, true, false},
    {"--no-vsync", false, true, false},
    {"--no-panel", false, true, false},
    {"--steps-per-frame", false, true, false},
    {"--screenshot-panel", false, true, false},
    {"--neighbour-lanes", true, false, true},
};

bool usedIn(const OptionUse& use, PlayMode mode) {
    return mode == PlayMode::Headless ? use.headless
           : mode == PlayMode::Window ? use.window
                                      : use.bench;
}

PlayWarning unusedOption(const std::string& option, const std::string& why) {
    return {"unused-option", option + " does nothing " + why};
}

} // namespace

/// Options given that do nothing in `mode`, or nothing without another option.
void checkOptionUse(const CLI::App& app, const PlayOptions& o, PlayMode mode,
                    std::vector<PlayWarning>& out) {
    const auto given = [&](const char* name) { return app.count(name) > 0; };
    for (const OptionUse& use : kOptionUses)
        if (given(use.name) && !usedIn(use, mode))
            out.push_back(unusedOption(use.name, modeWords(mode)));
    if (mode == PlayMode::Headless && given("--dump-every") && o.plyDir.empty())
        out.push_back(unusedOption("--dump-every", "without --dump-ply"));
    if (mode == PlayMode::Headless && o.surfaceDir.empty() && given("--surface-every"))
        out.push_back(unusedOption("--surface-every", "without --surface-mesh"));
    if (mode != PlayMode::Bench && given("--every") && !o.capture.frames())
        out.push_back(unusedOption("--every", "without --frames or --video"));
    if (mode != PlayMode::Bench && given("--fps") && o.capture.video.empty())
        out.push_back(unusedOption("--fps", "without --video"));
    if (mode == PlayMode::Headless && given("--shots") && !o.capture.screenshotAt)
        out.push_back(unusedOption("--shots", "in a --headless run without --screenshot-at"));
    const bool renders = mode == PlayMode::Window ||
                         (mode == PlayMode::Headless && o.capture.any()) ||
                         (mode == PlayMode::Bench && o.benchFrames > 0);
    const char* renderWhy = mode == PlayMode::Bench
                                ? "with --bench without --bench-frames"
                                : "in a --headless run without --frames, --video or "
                                  "--screenshot-at";
    for (const char* name :
         {"--size", "--colour", "--surface", "--zoom", "--raster-spheres", "--no-domain-box"})
        if (given(name) && !renders)
            out.push_back(unusedOption(name, renderWhy));
    // The mesh options shape the exported meshes and the drawn mesh mode (which M reaches in
    // the window) alike.
    const bool drawsMesh =
        renders && (mode == PlayMode::Window || parseSurfaceMode(o.surface) == SurfaceMode::Mesh);
    for (const char* name : {"--surface-cell", "--surface-iso", "--surface-kernel",
                             "--surface-normalised", "--surface-anisotropic"})
        if (given(name) && o.surfaceDir.empty() && !drawsMesh)
            out.push_back(unusedOption(name, mode == PlayMode::Bench
                                                 ? "with --bench without --bench-frames and "
                                                   "--surface mesh"
                                                 : "without --surface-mesh or --surface mesh"));
}

/// --bodies-csv for a scene without dynamic bodies would write only the header.
void checkBodiesCsv(const CLI::App& app, const format::Scene& scene, PlayMode mode,
                    std::vector<PlayWarning>& out) {
    if (mode != PlayMode::Headless || app.count("--bodies-csv") == 0)
        return;
    for (const format::SceneCollider& collider : scene.colliders)
        if (collider.dynamic)
            return;
    out.push_back(unusedOption("--bodies-csv", "for a scene without dynamic bodies (its table "
                                               "would have only the header)"));
}

SurfaceOptions surfaceOptions(const PlayOptions& o) {
    SurfaceOptions options;
    options.cellSize = o.surfaceCell;
    options.iso = o.surfaceIso;
    options.anisotropic = o.surfaceAnisotropic;
    options.kernel =
        o.surfaceKernel == "poly6" ? SurfaceFieldKernel::Poly6 : SurfaceFieldKernel::Gaussian;
    options.densityNormalised = o.surfaceNormalised;
    return options;
}

/// --surface-cell and --surface-iso against the scene's particle radius, before anything runs
/// (they shape the exported meshes and the drawn ones alike).
Result<void> checkSurfaceOptions(const PlayOptions& o, const format::Scene& scene) {
    SurfaceOptions options = surfaceOptions(o);
    options.particleRadius = 0.5f * scene.simulation.spacing;
    auto resolved = resolveSurfaceOptions(options);
    if (!resolved)
        return fail(ErrorCode::InvalidArgument,
                    "--surface-cell " + std::to_string(o.surfaceCell) + " / --surface-iso " +
                        std::to_string(o.surfaceIso) + ": " + resolved.error().detail);
    return {};
}

/// A --screenshot-at step the run never reaches.
void checkScreenshotStep(const PlayOptions& o, PlayMode mode, std::vector<PlayWarning>& out) {
    if (!o.capture.screenshotAt)
        return;
    const std::uint64_t at = *o.capture.screenshotAt;
    std::uint64_t last = 0;
    std::string limit;
    if (mode == PlayMode::Headless) {
        last = o.steps;
        limit = "--steps " + std::to_string(o.steps);
    } else if (mode == PlayMode::Window && o.maxFrames > 0) {
        // Frame f shows step f * stepsPerFrame; the last frame is maxFrames - 1.
        last = (o.maxFrames - 1) * o.stepsPerFrame;
        limit = "--max-frames " + std::to_string(o.maxFrames) + " shows steps up to " +
                std::to_string(last);
    } else {
        return;
    }
    if (at > last)
        out.push_back({"screenshot-after-end", "--screenshot-at " + std::to_string(at) +
                                                   " is after the last step (" + limit +
                                                   "): no screenshot would be written"});
}

} // namespace sluice::rt
