// runPlay: the sluice-play command line (CLI11), the headless run loop with its optional frame
// capture, and the hand-over to the viewer window.
#include "sluice/rt/play/PlayCli.h"

#include <exception>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "capture/CaptureFrames.h"
#include "capture/CaptureVideo.h"
#include "output/RunOutputs.h"
#include "play/Bench.h"
#include "play/PlayHeadless.h"
#include "play/PlayOptions.h"
#include "play/SceneChecks.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/format/support/CliErrors.h"
#include "sluice/rt/render/Renderer.h"
#include "sluice/rt/sim/Simulation.h"
#include "viewer/Viewer.h"

namespace sluice::rt {
namespace {

constexpr const char* kExitCodeHelp = R"(Exit codes:
  0  success
  1  --check: a particle went non-finite or ended inside a collider, or a body was lost
  2  bad input: scene file, collider asset or command-line value; no ffmpeg for --video
  3  no OpenGL 4.5 core context with compute shaders; no display for the window
  4  internal error
  130, 143  stopped by SIGINT (Ctrl-C) or SIGTERM: the run ended after the current step and
            wrote its outputs up to it (a second Ctrl-C quits at once)

Without --headless, sluice-play opens a window (GLFW): drag to orbit, right or middle drag to
pan, wheel to zoom; F1 lists the keys. --frames, --video and --screenshot-at capture in
both modes (headless through EGL into an offscreen framebuffer).

Before the first step sluice-play warns on stderr about likely mistakes: fluid outside the
domain box or in a collider, a collider far from the scene's scale, a body lighter or denser
than real materials or outside the domain, a fixed odd number of solver iterations, a
--screenshot-at after the last step, options that do nothing in the chosen mode. --strict makes
them errors (exit 2).
Output files and folders are checked, and their folders created, before any work starts.)";

/// --size (or `defaultSize` when it is not given), --colour and --surface.
Result<void> parseRendering(const PlayOptions& o, const char* defaultSize, glm::uvec2& size,
                            RenderSettings& settings) {
    auto parsed = parseImageSize(o.size.empty() ? defaultSize : o.size);
    if (!parsed)
        return parsed.error();
    size = *parsed;
    const auto colour = parseColourMode(o.colour);
    if (!colour)
        return fail(ErrorCode::InvalidArgument,
                    "--colour " + o.colour + ": expected water, speed or density");
    const auto surface = parseSurfaceMode(o.surface);
    if (!surface)
        return fail(ErrorCode::InvalidArgument,
                    "--surface " + o.surface + ": expected spheres, fluid or mesh");
    settings.colour = *colour;
    settings.surface = *surface;
    settings.computeSmallSpheres = !o.rasterSpheres;
    settings.drawDomainBox = !o.noDomainBox;
    settings.mesh = surfaceOptions(o);
    return {};
}

/// The scene and its colliders, read once, before any GL work.
struct LoadedScene {
    format::Scene scene;
    std::vector<format::ColliderAsset> colliders;
};

Result<LoadedScene> loadScene(const std::string& path) {
    auto scene = format::readScene(path);
    if (!scene)
        return scene.error();
    auto colliders = loadSceneColliders(*scene);
    if (!colliders)
        return colliders.error();
    return LoadedScene{std::move(*scene), std::move(*colliders)};
}

/// Prints the warnings on stderr; with --strict any of them stops the run before the first
/// step: the exit code then.
std::optional<int> reportWarnings(const std::vector<PlayWarning>& warnings, bool strict) {
    for (const PlayWarning& warning : warnings)
        std::cerr << warningLine(warning) << '\n';
    if (!strict || warnings.empty())
        return std::nullopt;
    if (warnings.size() == 1)
        std::cerr << "sluice-play: --strict turned the warning above into an error";
    else
        std::cerr << "sluice-play: --strict turned the " << warnings.size()
                  << " warnings above into errors";
    std::cerr << "; nothing was run\n";
    return kExitBadInput;
}

/// The files and folders a run in `mode` writes.
std::vector<RunOutput> runOutputs(const PlayOptions& o, PlayMode mode) {
    if (mode == PlayMode::Bench)
        return {{"--bench-json", o.benchJson, false}};
    std::vector<RunOutput> outputs = {{"--frames", o.capture.framesDir, true},
                                      {"--video", o.capture.video, false}};
    // Headless runs write into --shots only for --screenshot-at; the window's P key uses it too.
    if (mode == PlayMode::Window || o.capture.screenshotAt)
        outputs.push_back({"--shots", o.capture.shotsDir, true});
    if (mode == PlayMode::Headless) {
        outputs.push_back({"--stats-json", o.statsJson, false});
        outputs.push_back({"--dump-ply", o.plyDir, true});
        outputs.push_back({"--bodies-csv", o.bodiesCsv, false});
        outputs.push_back({"--surface-mesh", o.surfaceDir, true});
    }
    return outputs;
}

/// The image size and render settings of a run (--size, --colour, --surface).
struct Rendering {
    glm::uvec2 size{0};
    RenderSettings settings;
};

/// The rendering flags of `mode`, checked before anything is read or written. A bench without
/// --bench-frames renders nothing and leaves them unchecked.
Result<Rendering> parseModeRendering(const PlayOptions& o, PlayMode mode) {
    Rendering r;
    if (mode == PlayMode::Bench && o.benchFrames == 0)
        return r;
    const char* defaultSize = mode == PlayMode::Bench ? "1920x1080" : "1280x720";
    if (auto ok = parseRendering(o, defaultSize, r.size, r.settings); !ok)
        return ok.error();
    return r;
}

int startBench(const PlayOptions& o, const Rendering& rendering, LoadedScene loaded) {
    BenchOptions bench;
    bench.steps = o.steps > 0 ? o.steps : 100;
    bench.warmup = o.warmup;
    bench.json = o.benchJson;
    bench.deterministic = o.deterministic;
    bench.neighbourLanes = o.neighbourLanes;
    bench.renderFrames = o.benchFrames;
    bench.zoom = o.capture.zoom;
    if (o.benchFrames > 0) {
        bench.renderSize = rendering.size;
        bench.render = rendering.settings;
    }
    return runBench(bench, loaded.scene, std::move(loaded.colliders));
}

int startWindow(const PlayOptions& o, const Rendering& rendering, const LoadedScene& loaded) {
    ViewerOptions viewer;
    viewer.scene = o.scene;
    viewer.capture = o.capture;
    viewer.maxFrames = o.maxFrames;
    viewer.vsync = !o.noVsync;
    viewer.panel = !o.noPanel;
    viewer.screenshotPanel = o.screenshotPanel;
    viewer.deterministic = o.deterministic;
    viewer.stepsPerFrame = o.stepsPerFrame;
    viewer.quiet = o.quiet;
    viewer.size = rendering.size;
    viewer.settings = rendering.settings;
    if (!o.quiet)
        for (const std::string& line : describeColliders(loaded.scene, loaded.colliders))
            std::cout << "sluice-play: " << line << '\n';
    return runViewer(viewer);
}

int startHeadless(const PlayOptions& o, const Rendering& rendering, LoadedScene loaded) {
    HeadlessOptions headless;
    headless.steps = o.steps;
    headless.statsEvery = o.statsEvery;
    headless.statsJson = o.statsJson;
    headless.plyDir = o.plyDir;
    headless.bodiesCsv = o.bodiesCsv;
    headless.surfaceDir = o.surfaceDir;
    headless.surfaceEvery = o.surfaceEvery;
    headless.surface = surfaceOptions(o);
    headless.dumpEvery = o.dumpEvery;
    headless.deterministic = o.deterministic;
    headless.neighbourLanes = o.neighbourLanes;
    headless.check = o.check;
    headless.quiet = o.quiet;
    headless.capture = o.capture;
    headless.imageSize = rendering.size;
    headless.render = rendering.settings;
    return playHeadless(headless, loaded.scene, std::move(loaded.colliders));
}

/// After the command line: checks the rendering flags and ffmpeg, reads the scene, warns,
/// prepares the outputs, runs `mode`. Nothing is written before the outputs are prepared.
int play(const CLI::App& app, const PlayOptions& o, PlayMode mode) {
    const auto rendering = parseModeRendering(o, mode);
    if (!rendering)
        return reportFailure(rendering.error());
    if (mode != PlayMode::Bench && !o.capture.video.empty())
        if (auto ffmpeg = findFfmpeg(); !ffmpeg)
            return reportFailure(ffmpeg.error());
    std::vector<PlayWarning> warnings;
    checkOptionUse(app, o, mode, warnings);
    checkScreenshotStep(o, mode, warnings);
    auto loaded = loadScene(o.scene);
    if (!loaded)
        return reportFailure(loaded.error());
    for (PlayWarning& warning : checkScene(loaded->scene, loaded->colliders))
        warnings.push_back(std::move(warning));
    checkBodiesCsv(app, loaded->scene, mode, warnings);
    if (auto ok = checkSurfaceOptions(o, loaded->scene); !ok)
        return reportFailure(ok.error());
    if (auto stop = reportWarnings(warnings, o.strict))
        return *stop;
    if (auto ok = prepareRunOutputs(runOutputs(o, mode)); !ok)
        return reportFailure(ok.error());
    switch (mode) {
    case PlayMode::Bench:
        return startBench(o, *rendering, std::move(*loaded));
    case PlayMode::Window:
        return startWindow(o, *rendering, *loaded);
    case PlayMode::Headless:
        return startHeadless(o, *rendering, std::move(*loaded));
    }
    return kExitInternal;
}

// [steps] most steps (and step intervals) the options take: checked, never advertised.
constexpr std::uint64_t kMaxSteps = std::uint64_t{1} << 40;

// The scene, the run's length, its outputs and checks.
void addRunOptions(CLI::App& app, PlayOptions& o) {
    app.add_option("scene", o.scene, "Scene file (.json)")->required();
    app.add_flag("--headless", o.headless, "Run without a window (EGL), printing statistics");
    app.add_option("--steps", o.steps, "Steps to run (each is the scene's timeStep)")
        ->check(format::cli::countAtLeast(1, kMaxSteps, "steps"));
    app.add_option("--stats-every", o.statsEvery,
                   "Record statistics every K steps (default: about 20 rows)")
        ->check(format::cli::countAtLeast(1, kMaxSteps, "steps"));
    app.add_option("--stats-json", o.statsJson, "Write the recorded statistics to this JSON file");
    app.add_option("--dump-ply", o.plyDir, "Write particle PLY files into this folder");
    app.add_option("--bodies-csv", o.bodiesCsv,
                   "Write every dynamic body's trajectory (one row per recorded step and body) "
                   "to this CSV file");
    app.add_option("--surface-mesh", o.surfaceDir,
                   "Write the fluid's surface as a triangle mesh (surface_STEP.ply) into this "
                   "folder, at step 0 and every --surface-every steps");
    app.add_option("--surface-every", o.surfaceEvery, "A surface mesh every K steps (default 1)")
        ->check(format::cli::countAtLeast(1, kMaxSteps, "steps"));
    app.add_option("--surface-cell", o.surfaceCell,
                   "Surface mesh: sample spacing [m] (default: the particle radius)")
        ->check(format::cli::numberIn(1e-6, 1e3));
    app.add_option("--surface-iso", o.surfaceIso,
                   "Surface mesh: iso value, a share of the field inside the fluid (default 0.6; "
                   "0.5 with --no-surface-normalised)")
        ->check(format::cli::numberIn(0.01, 3.99));
    app.add_option("--surface-kernel", o.surfaceKernel,
                   "Surface mesh: the kernel round each particle, gaussian (default: as wide as "
                   "poly6, deposited and blurred; several times faster on a software renderer) "
                   "or poly6 (splatted particle by particle); anisotropic kernels are poly6")
        ->check(CLI::IsMember({"gaussian", "poly6"}));
    app.add_flag_function(
           "--surface-normalised,!--no-surface-normalised",
           [&o](std::int64_t count) { o.surfaceNormalised = count > 0; },
           "Surface mesh: each particle's kernel scaled by the rest density over its own, as "
           "splashsurf does (thin sheets and droplets keep their volume; iso default 0.6), or "
           "--no-surface-normalised by the rest volume alone (one field pass; iso default 0.5). "
           "Default: normalised, but not with --surface-anisotropic")
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast); // the last one given wins
    app.add_flag("--surface-anisotropic", o.surfaceAnisotropic,
                 "Surface meshes, exported and drawn (--surface mesh): anisotropic kernels, "
                 "flat across surfaces and thin sheets (docs/surfaces.md)");
    app.add_option("--dump-every", o.dumpEvery, "Write a PLY file every K steps (default 1)")
        ->check(format::cli::countAtLeast(1, kMaxSteps, "steps"));
    app.add_flag("--deterministic", o.deterministic,
                 "Fixed particle order inside hash buckets: identical results run to run");
    app.add_option("--neighbour-lanes", o.neighbourLanes,
                   "Invocations per particle in the solver's neighbour passes: 1, 2, 4, 8, 16 or "
                   "32 (default: 1 on a software renderer, on a GPU enough to fill it)")
        ->check(CLI::IsMember({1, 2, 4, 8, 16, 32}));
    app.add_flag("--check", o.check,
                 "Exit 1 if a particle went non-finite or ended inside a collider");
    app.add_flag("--quiet", o.quiet, "Print nothing but errors");
    app.add_flag("--strict", o.strict,
                 "Treat every warning (scene checks, options that do nothing) as an error: "
                 "exit 2 before the first step");
}

// --bench and what it measures.
void addBenchOptions(CLI::App& app, PlayOptions& o) {
    app.add_flag("--bench", o.bench,
                 "Benchmark (headless): warm up, then the median step and pass times over --steps");
    app.add_option("--warmup", o.warmup, "Steps run before --bench measures (default 20)");
    app.add_option("--bench-json", o.benchJson, "Write the --bench results to this JSON file");
    app.add_option("--bench-frames", o.benchFrames,
                   "With --bench: render N frames of the final state at --size (1920x1080), "
                   "waiting for each, and report every render pass's median GPU time")
        ->check(format::cli::wholeNumber(1, 100000));
}

// Pictures, video and the look of the frames, in a headless run and in the window.
void addCaptureOptions(CLI::App& app, PlayOptions& o) {
    app.add_option("--frames", o.capture.framesDir,
                   "Write a PNG of every --every-th step into this folder (frame_STEP.png)");
    app.add_option("--every", o.capture.every, "Capture every K steps, from step 0 (default 1)")
        ->check(format::cli::countAtLeast(1, kMaxSteps, "steps"));
    app.add_option("--video", o.capture.video,
                   "Encode the captured frames into this MP4 file (needs ffmpeg)");
    app.add_option("--fps", o.capture.fps,
                   "Frames per second of --video (default: real time, 1 / (every * timeStep))")
        ->check(format::cli::finiteNumber(false));
    app.add_option(
        "--size", o.size,
        "Image size WIDTHxHEIGHT: capture and the window (1280x720), --bench-frames (1920x1080)");
    app.add_option("--zoom", o.capture.zoom,
                   "The scene camera's distance times this (0.7: closer), window and capture")
        ->check(format::cli::numberIn(0.01, 100.0));
    app.add_option("--colour", o.colour, "Particle colours: water, speed or density (error)");
    app.add_option("--surface", o.surface,
                   "Fluid drawn as spheres, a screen-space fluid surface or the reconstructed "
                   "surface mesh: spheres, fluid or mesh");
    app.add_flag("--raster-spheres", o.rasterSpheres,
                 "Rasterise every particle sphere (default: the ones of at most 8x8 pixels in a "
                 "compute pass, the same pixels)");
    app.add_flag("--no-domain-box", o.noDomainBox,
                 "Do not draw the domain box's edges (drawn by default where the scene has one)");
    app.add_option("--screenshot-at", o.capture.screenshotAt,
                   "Write one PNG of step N (NAME-STEP.png), as the window's P key does");
    app.add_option("--shots", o.capture.shotsDir,
                   "Folder of screenshots: --screenshot-at and the window's P key (default: .)");
}

// The window only (and its screenshots with the panel).
void addWindowOptions(CLI::App& app, PlayOptions& o) {
    app.add_option("--max-frames", o.maxFrames, "Window: close after N frames (tests, demos)");
    app.add_flag("--no-vsync", o.noVsync, "Window: do not wait for the display's refresh");
    app.add_flag("--no-panel", o.noPanel, "Window: start with the parameter panel hidden");
    app.add_option("--steps-per-frame", o.stepsPerFrame, "Window: steps per frame (default 1)")
        ->check(format::cli::wholeNumber(1, 1000));
    app.add_flag("--screenshot-panel", o.screenshotPanel,
                 "Window: screenshots (P, --screenshot-at) include the panel, for bug reports; "
                 "the O key toggles it");
}

int run(int argc, char** argv) {
    CLI::App app{"sluice-play: plays a Sluice fluid scene (Position Based Fluids on the GPU).",
                 "sluice-play"};
    app.set_version_flag("--version", std::string("sluice-play ") + SLUICE_VERSION);
    app.footer(kExitCodeHelp);
    PlayOptions o;
    addRunOptions(app, o);
    addBenchOptions(app, o);
    addCaptureOptions(app, o);
    addWindowOptions(app, o);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version arrive here too, and exit 0.
        return format::cli::reportParseError(app, e, "sluice-play", kExitBadInput);
    }
    if (o.benchFrames > 0 && !o.bench) {
        std::cerr << "sluice-play: --bench-frames needs --bench\n";
        return kExitBadInput;
    }
    if (!o.bench && o.headless && o.steps == 0) {
        std::cerr << "sluice-play: --headless needs --steps N\n";
        return kExitBadInput;
    }
    return play(app, o,
                o.bench      ? PlayMode::Bench
                : o.headless ? PlayMode::Headless
                             : PlayMode::Window);
}

} // namespace

int reportFailure(const Error& error) {
    std::cerr << "sluice-play: " << error.message() << '\n';
    return exitCodeFor(error);
}

int runPlay(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "sluice-play: internal error: " << e.what() << '\n';
    } catch (...) {
        std::cerr << "sluice-play: internal error (unknown exception)\n";
    }
    return kExitInternal;
}

} // namespace sluice::rt
