// runPlay: the sluice-play command line (CLI11) and the headless run loop.
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
#include "StatsReport.h"
#include "sluice/format/AtomicFile.h"
#include "sluice/format/SceneIO.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/PlyWriter.h"
#include "sluice/rt/Simulation.h"

namespace sluice::rt {
namespace {

constexpr const char* kExitCodeHelp = R"(Exit codes:
  0  success
  1  --check: a particle went non-finite or ended inside a collider
  2  bad input: scene file, collider asset or command-line value
  3  no OpenGL 4.5 core context with compute shaders
  4  internal error)";

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
};

int exitCodeFor(const Error& error) {
    switch (error.code) {
    case ErrorCode::NoGlContext: return kPlayExitNoGlContext;
    case ErrorCode::ShaderCompile:
    case ErrorCode::ShaderLink: return kPlayExitInternal;
    default: return kPlayExitBadInput;
    }
}

int fail(const Error& error) {
    std::cerr << "sluice-play: " << error.message() << '\n';
    return exitCodeFor(error);
}

std::string plyName(std::uint64_t step) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06llu.ply", static_cast<unsigned long long>(step));
    return name;
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

    auto context = gpu::Context::createHeadless();
    if (!context)
        return fail(context.error());
    SimulationOptions simOptions;
    simOptions.deterministic = o.deterministic;
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
        // The capacity flag is cheap to read (CPU side); report it once.
        if (!capacityReported && sim->particleCount() == sim->capacity() &&
            !scene->emitters.empty()) {
            std::cerr << "sluice-play: step " << step << ": particle capacity "
                      << sim->capacity() << " reached; emitters stop adding particles\n";
            capacityReported = true;
        }
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
    app.add_option("--steps", o.steps, "Steps to run (each is the scene's timeStep)")
        ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 40));
    app.add_option("--stats-every", o.statsEvery,
                   "Record statistics every K steps (default: about 20 rows)")
        ->check(CLI::PositiveNumber);
    app.add_option("--stats-json", o.statsJson, "Write the recorded statistics to this JSON file");
    app.add_option("--dump-ply", o.plyDir, "Write particle PLY files into this folder");
    app.add_option("--dump-every", o.dumpEvery, "Write a PLY file every K steps (default 1)")
        ->check(CLI::PositiveNumber);
    app.add_flag("--deterministic", o.deterministic,
                 "Fixed particle order inside hash buckets: identical results run to run");
    app.add_flag("--check", o.check,
                 "Exit 1 if a particle went non-finite or ended inside a collider");
    app.add_flag("--quiet", o.quiet, "Print nothing but errors");
    app.add_flag("--bench", o.bench,
                 "Benchmark (headless): warm up, then the median step and pass times over --steps");
    app.add_option("--warmup", o.warmup, "Steps run before --bench measures (default 20)");
    app.add_option("--bench-json", o.benchJson, "Write the --bench results to this JSON file");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? kPlayExitOk : kPlayExitBadInput;
    }
    if (o.bench) {
        BenchOptions bench;
        bench.scene = o.scene;
        bench.steps = o.steps > 0 ? o.steps : 100;
        bench.warmup = o.warmup;
        bench.json = o.benchJson;
        bench.deterministic = o.deterministic;
        return runBench(bench);
    }
    if (!o.headless) {
        std::cerr << "sluice-play: the viewer window is not built yet; run with --headless\n";
        return kPlayExitBadInput;
    }
    if (o.steps == 0) {
        std::cerr << "sluice-play: --headless needs --steps N\n";
        return kPlayExitBadInput;
    }
    return playHeadless(o);
}

} // namespace

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
