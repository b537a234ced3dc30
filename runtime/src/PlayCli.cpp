// runPlay: the sluice-play command line (CLI11), the headless run loop with its optional frame
// capture, and the hand-over to the viewer window.
#include "sluice/rt/PlayCli.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "Bench.h"
#include "CaptureFrames.h"
#include "CaptureHeadless.h"
#include "StatsReport.h"
#include "Viewer.h"
#include "sluice/format/AtomicFile.h"
#include "sluice/format/CliErrors.h"
#include "sluice/format/SceneIO.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/PlyWriter.h"
#include "sluice/rt/Simulation.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {
namespace {

constexpr const char* kExitCodeHelp = R"(Exit codes:
  0  success
  1  --check: a particle went non-finite or ended inside a collider
  2  bad input: scene file, collider asset or command-line value; no ffmpeg for --video
  3  no OpenGL 4.5 core context with compute shaders; no display for the window
  4  internal error

Without --headless, sluice-play opens a window (GLFW): drag to orbit, right or middle drag to
pan, wheel to zoom; F1 lists the keys. --frames, --video and --screenshot-at capture in
both modes (headless through EGL into an offscreen framebuffer).)";

struct PlayOptions {
    std::string scene;
    bool headless = false;
    std::uint64_t steps = 0;
    std::uint64_t statsEvery = 0; // 0: about 20 rows over the run
    std::string statsJson;
    std::string plyDir;
    std::uint64_t dumpEvery = 1;
    bool deterministic = false;
    bool check = false;
    bool quiet = false;
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
    std::uint32_t stepsPerFrame = 1;
};

int fail(const Error& error) {
    std::cerr << "sluice-play: " << error.message() << '\n';
    return playExitCode(error);
}

std::string plyName(std::uint64_t step) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06llu.ply", static_cast<unsigned long long>(step));
    return name;
}

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
                    "--surface " + o.surface + ": expected spheres or fluid");
    settings.colour = *colour;
    settings.surface = *surface;
    return {};
}

int playHeadless(const PlayOptions& o) {
    auto scene = format::readScene(o.scene);
    if (!scene)
        return fail(scene.error());
    auto colliders = loadSceneColliders(*scene);
    if (!colliders)
        return fail(colliders.error());
    if (!o.plyDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(o.plyDir, ec);
        if (ec)
            return fail({ErrorCode::Io, o.plyDir + ": cannot create the PLY folder: " +
                                            ec.message()});
    }

    glm::uvec2 imageSize;
    RenderSettings settings;
    if (auto ok = parseRendering(o, "1280x720", imageSize, settings); !ok)
        return fail(ok.error());

    auto context = gpu::Context::createHeadless();
    if (!context)
        return fail(context.error());
    SimulationOptions simOptions;
    simOptions.deterministic = o.deterministic;
    // The renderer uploads the colliders to 3D textures of its own before the solver takes them.
    std::optional<HeadlessCapture> capture;
    if (o.capture.any()) {
        auto started = HeadlessCapture::start(*scene, *colliders, o.capture, imageSize, settings);
        if (!started)
            return fail(started.error());
        capture.emplace(std::move(*started));
    }
    auto sim = Simulation::create(*scene, std::move(*colliders), simOptions);
    if (!sim)
        return fail(sim.error());

    const std::uint64_t every =
        o.statsEvery > 0 ? o.statsEvery : std::max<std::uint64_t>(1, o.steps / 20);
    if (!o.quiet) {
        std::cout << "scene " << scene->path << ": " << sim->particleCount() << " particles ("
                  << sim->capacity() << " capacity), " << scene->colliders.size()
                  << " colliders, " << scene->simulation.substeps << " substeps of "
                  << sim->constants().dt * 1e3 << " ms, up to " << scene->simulation.maxIterations
                  << " iterations\n"
                  << "GL: " << context->info().renderer << "\n\n"
                  << statsTableHeader();
    }

    nlohmann::json steps = nlohmann::json::array();
    bool dirty = false;
    bool capacityReported = false;
    auto dump = [&](std::uint64_t step) -> Result<void> {
        if (o.plyDir.empty() || step % o.dumpEvery != 0)
            return {};
        const auto particles = sim->downloadParticles();
        return writePly(std::filesystem::path(o.plyDir) / plyName(step), particles);
    };
    if (auto ok = dump(0); !ok)
        return fail(ok.error());
    auto captureStep = [&](std::uint64_t step) -> Result<void> {
        return capture ? capture->afterStep(*sim, step) : Result<void>{};
    };
    if (auto ok = captureStep(0); !ok)
        return fail(ok.error());

    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t step = 1; step <= o.steps; ++step) {
        sim->step();
        if (step % every == 0 || step == o.steps) {
            const StepStats stats = sim->readStats();
            const PassTimes times = sim->passTimes();
            double gpuMs = 0.0;
            for (double t : times)
                gpuMs += t > 0.0 ? t : 0.0;
            if (!o.quiet)
                std::cout << statsTableRow(stats, gpuMs > 0.0 ? gpuMs : -1.0);
            steps.push_back(statsJson(stats));
            if (stats.nonFinite > 0) {
                std::cerr << "sluice-play: step " << stats.step << ": " << stats.nonFinite
                          << " particles went non-finite and were reset to their last position\n";
                dirty = true;
            }
            if (stats.insideColliders > 0)
                dirty = true;
        }
        if (auto ok = dump(step); !ok)
            return fail(ok.error());
        if (auto ok = captureStep(step); !ok)
            return fail(ok.error());
        // The capacity flag is cheap to read (CPU side); report it once.
        if (!capacityReported && sim->particleCount() == sim->capacity() &&
            !scene->emitters.empty()) {
            std::cerr << "sluice-play: step " << step << ": particle capacity "
                      << sim->capacity() << " reached; emitters stop adding particles\n";
            capacityReported = true;
        }
    }
    if (capture) {
        if (auto ok = capture->finish(); !ok)
            return fail(ok.error());
    }
    glFinish();
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const PassTimes times = sim->passTimes();
    const double stepsPerSecond = wall > 0.0 ? double(o.steps) / wall : 0.0;

    if (!o.quiet) {
        std::cout << "\n" << o.steps << " steps in " << wall << " s wall: " << stepsPerSecond
                  << " steps/s (" << context->info().renderer << ")\nGPU ms per step:";
        for (std::size_t p = 0; p < times.size(); ++p)
            if (times[p] >= 0.0)
                std::cout << "  " << passName(Pass(p)) << " " << times[p];
        std::cout << "\n";
        if (capture)
            capture->report(std::cout);
    }

    if (!o.statsJson.empty()) {
        nlohmann::json doc = {
            {"tool", std::string("sluice-play ") + SLUICE_VERSION},
            {"scene", scene->path},
            {"name", scene->name},
            {"deterministic", o.deterministic},
            {"parameters", parametersJson(scene->simulation, sim->constants())},
            {"capacity", sim->capacity()},
            {"steps", steps},
        };
        // Timings differ run to run; a deterministic run leaves them out so its file is
        // byte-identical every time.
        if (!o.deterministic)
            doc["timing"] = {{"renderer", context->info().renderer},
                             {"wallSeconds", wall},
                             {"stepsPerSecond", stepsPerSecond},
                             {"gpuMsPerStep", passTimesJson(times)}};
        const std::string text = doc.dump(2) + "\n";
        auto ok = format::writeFileAtomic(
            o.statsJson, std::as_bytes(std::span(text.data(), text.size())));
        if (!ok)
            return fail(ok.error());
    }
    if (o.check && dirty) {
        std::cerr << "sluice-play: --check: particles went non-finite or ended inside a "
                     "collider (see the table)\n";
        return kPlayExitCheckFailed;
    }
    return kPlayExitOk;
}

int run(int argc, char** argv) {
    CLI::App app{"sluice-play: plays a Sluice fluid scene (Position Based Fluids on the GPU).",
                 "sluice-play"};
    app.set_version_flag("--version", std::string("sluice-play ") + SLUICE_VERSION);
    app.footer(kExitCodeHelp);
    PlayOptions o;
    app.add_option("scene", o.scene, "Scene file (.json)")->required();
    app.add_flag("--headless", o.headless, "Run without a window (EGL), printing statistics");
    // [steps] most steps (and step intervals) the options take: checked, never advertised.
    constexpr std::uint64_t kMaxSteps = std::uint64_t{1} << 40;
    app.add_option("--steps", o.steps, "Steps to run (each is the scene's timeStep)")
        ->check(format::cli::countAtLeast(1, kMaxSteps, "steps"));
    app.add_option("--stats-every", o.statsEvery,
                   "Record statistics every K steps (default: about 20 rows)")
        ->check(format::cli::countAtLeast(1, kMaxSteps, "steps"));
    app.add_option("--stats-json", o.statsJson, "Write the recorded statistics to this JSON file");
    app.add_option("--dump-ply", o.plyDir, "Write particle PLY files into this folder");
    app.add_option("--dump-every", o.dumpEvery, "Write a PLY file every K steps (default 1)")
        ->check(format::cli::countAtLeast(1, kMaxSteps, "steps"));
    app.add_flag("--deterministic", o.deterministic,
                 "Fixed particle order inside hash buckets: identical results run to run");
    app.add_flag("--check", o.check,
                 "Exit 1 if a particle went non-finite or ended inside a collider");
    app.add_flag("--quiet", o.quiet, "Print nothing but errors");
    app.add_flag("--bench", o.bench,
                 "Benchmark (headless): warm up, then the median step and pass times over --steps");
    app.add_option("--warmup", o.warmup, "Steps run before --bench measures (default 20)");
    app.add_option("--bench-json", o.benchJson, "Write the --bench results to this JSON file");
    app.add_option("--bench-frames", o.benchFrames,
                   "With --bench: render N frames of the final state at --size (1920x1080), "
                   "waiting for each, and report every render pass's median GPU time")
        ->check(format::cli::wholeNumber(1, 100000));
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
                   "Fluid drawn as spheres or as a screen-space fluid surface: spheres or fluid");
    app.add_option("--max-frames", o.maxFrames, "Window: close after N frames (tests, demos)");
    app.add_flag("--no-vsync", o.noVsync, "Window: do not wait for the display's refresh");
    app.add_flag("--no-panel", o.noPanel, "Window: start with the parameter panel hidden");
    app.add_option("--steps-per-frame", o.stepsPerFrame, "Window: steps per frame (default 1)")
        ->check(format::cli::wholeNumber(1, 1000));
    app.add_option("--screenshot-at", o.capture.screenshotAt,
                   "Write one PNG of step N (NAME-STEP.png), as the window's P key does");
    app.add_option("--shots", o.capture.shotsDir,
                   "Folder of screenshots: --screenshot-at and the window's P key (default: .)");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version arrive here too, and exit 0.
        return format::cli::reportParseError(app, e, "sluice-play", kPlayExitBadInput);
    }
    if (o.benchFrames > 0 && !o.bench) {
        std::cerr << "sluice-play: --bench-frames needs --bench\n";
        return kPlayExitBadInput;
    }
    if (o.bench) {
        BenchOptions bench;
        bench.scene = o.scene;
        bench.steps = o.steps > 0 ? o.steps : 100;
        bench.warmup = o.warmup;
        bench.json = o.benchJson;
        bench.deterministic = o.deterministic;
        bench.renderFrames = o.benchFrames;
        bench.zoom = o.capture.zoom;
        if (o.benchFrames > 0)
            if (auto ok = parseRendering(o, "1920x1080", bench.renderSize, bench.render); !ok)
                return fail(ok.error());
        return runBench(bench);
    }
    if (!o.headless) {
        ViewerOptions viewer;
        viewer.scene = o.scene;
        viewer.capture = o.capture;
        viewer.maxFrames = o.maxFrames;
        viewer.vsync = !o.noVsync;
        viewer.panel = !o.noPanel;
        viewer.deterministic = o.deterministic;
        viewer.stepsPerFrame = o.stepsPerFrame;
        viewer.quiet = o.quiet;
        if (auto ok = parseRendering(o, "1280x720", viewer.size, viewer.settings); !ok)
            return fail(ok.error());
        return runViewer(viewer);
    }
    if (o.steps == 0) {
        std::cerr << "sluice-play: --headless needs --steps N\n";
        return kPlayExitBadInput;
    }
    return playHeadless(o);
}

} // namespace

int playExitCode(const Error& error) {
    switch (error.code) {
    case ErrorCode::NoGlContext: return kPlayExitNoGlContext;
    case ErrorCode::ShaderCompile:
    case ErrorCode::ShaderLink: return kPlayExitInternal;
    default: return kPlayExitBadInput;
    }
}

int runPlay(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "sluice-play: internal error: " << e.what() << '\n';
    } catch (...) {
        std::cerr << "sluice-play: internal error (unknown exception)\n";
    }
    return kPlayExitInternal;
}

} // namespace sluice::rt
