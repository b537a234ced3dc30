// The headless run loop: statistics rows, PLY dumps and captured frames after each step, then
// the timing summary and the statistics file.
#include "play/PlayHeadless.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <span>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "capture/CaptureHeadless.h"
#include "output/BodiesCsv.h"
#include "output/StatsReport.h"
#include "play/Interrupt.h"
#include "play/RunProgress.h"
#include "play/SceneChecks.h"
#include "sluice/format/support/AtomicFile.h"
#include "sluice/format/support/Suggest.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/play/PlayCli.h"
#include "sluice/rt/play/PlyWriter.h"
#include "sluice/rt/sim/Simulation.h"
#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::rt {
namespace {

std::string plyName(std::uint64_t step) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06llu.ply", static_cast<unsigned long long>(step));
    return name;
}

/// Everything one headless run keeps between steps.
struct HeadlessRun {
    const HeadlessOptions& options;
    const format::Scene& scene;
    const gpu::Context& context;
    Simulation sim;
    std::optional<HeadlessCapture> capture;
    std::optional<SurfaceReconstructor> surfaces;   ///< --surface-mesh
    BodiesCsv bodiesCsv;                            ///< --bodies-csv rows
    RunProgress progress;                           ///< the terminal's progress line
    std::uint64_t statsEvery = 1;                   ///< a statistics row every this many steps
    std::uint64_t stepsDone = 0;                    ///< steps run (fewer when interrupted)
    nlohmann::json steps = nlohmann::json::array(); ///< the recorded statistics
    bool dirty = false;                 ///< a particle went non-finite or ended inside a collider,
                                        ///< or a body was put back (StepStats::bodyFaults)
    std::uint32_t bodyFaults = 0;       ///< StepStats::bodyFaults reported so far
    bool capacityReported = false;      ///< the full-capacity message was printed
    double wallSeconds = 0.0;           ///< the steps' wall time, capture included [s]
    PassTimes passTimes{};              ///< GPU time per pass after the last step [ms]
    std::vector<double> surfaceSeconds; ///< each surface mesh's reconstruction [s]
    std::vector<SurfaceTimings> surfaceStages; ///< and where its time went
    std::size_t surfaceVertices = 0;           ///< of the latest surface mesh
    std::size_t surfaceTriangles = 0;
    std::vector<double> surfaceWriteSeconds; ///< each surface mesh's PLY file [s]
};

/// Creates the capture (if any) and the simulation. The renderer uploads the colliders to 3D
/// textures of its own before the solver takes them.
Result<HeadlessRun> startRun(const HeadlessOptions& o, const format::Scene& scene,
                             std::vector<format::ColliderAsset> colliders,
                             const gpu::Context& context) {
    std::optional<HeadlessCapture> capture;
    if (o.capture.any()) {
        auto started = HeadlessCapture::start(scene, colliders, o.capture, o.imageSize, o.render);
        if (!started)
            return started.error();
        capture.emplace(std::move(*started));
    }
    if (auto warning = slowLoadWarning(scene, colliders))
        std::cerr << "sluice-play: warning [slow-load]: " << *warning << std::endl;
    SimulationOptions simOptions;
    simOptions.deterministic = o.deterministic;
    simOptions.timers = true; // the statistics table and summary report GPU time per pass
    simOptions.neighbourLanes = o.neighbourLanes;
    auto sim = Simulation::create(scene, std::move(colliders), simOptions);
    if (!sim)
        return sim.error();
    if (auto note = volumeMapNote(scene, sim->volumeMapLoad()); note && !o.quiet)
        std::cerr << "sluice-play: " << *note << std::endl;
    const std::uint64_t every =
        o.statsEvery > 0 ? o.statsEvery : std::max<std::uint64_t>(1, o.steps / 20);
    std::optional<SurfaceReconstructor> surfaces;
    if (!o.surfaceDir.empty()) {
        auto created = SurfaceReconstructor::create();
        if (!created)
            return created.error();
        surfaces.emplace(std::move(*created));
    }
    const bool progress = !o.quiet && RunProgress::stderrIsTerminal();
    return HeadlessRun{o,
                       scene,
                       context,
                       std::move(*sim),
                       std::move(capture),
                       std::move(surfaces),
                       BodiesCsv(o.bodiesCsv),
                       RunProgress(o.steps, progress),
                       every};
}

void printStartup(const HeadlessRun& run, const std::vector<std::string>& colliderLines) {
    const Simulation& sim = run.sim;
    std::cout << "scene " << run.scene.path << ": " << sim.particleCount() << " particles ("
              << sim.capacity() << " capacity), "
              << format::plural(run.scene.colliders.size(), "collider") << ", "
              << run.scene.simulation.substeps << " substeps of " << sim.constants().dt * 1e3
              << " ms, up to " << run.scene.simulation.maxIterations << " iterations\n";
    for (const std::string& line : colliderLines)
        std::cout << "  " << line << '\n';
    for (const BodyState& b : sim.bodies())
        std::cout << "  body: collider " << b.collider << ", " << b.mass << " kg, "
                  << b.volume * 1e3 << " L (mass properties from the "
                  << (b.massFromMesh ? "mesh" : "field") << ")\n";
    if (sim.particlesRemovedAtSpawn() > 0)
        std::cout << "  " << format::plural(sim.particlesRemovedAtSpawn(), "particle")
                  << " of the fluid blocks started inside a dynamic body and were left out\n";
    std::cout << "GL: " << run.context.info().renderer << "\n\n" << statsTableHeader();
}

std::string surfaceName(std::uint64_t step) {
    char name[32];
    std::snprintf(name, sizeof name, "surface_%06llu.ply", static_cast<unsigned long long>(step));
    return name;
}

/// The fluid's surface mesh of step `step`, where one is due.
Result<void> writeSurface(HeadlessRun& run, std::uint64_t step) {
    const HeadlessOptions& o = run.options;
    if (!run.surfaces || step % o.surfaceEvery != 0)
        return {};
    SurfaceOptions options = o.surface;
    options.particleRadius = run.sim.constants().radius;
    const auto start = std::chrono::steady_clock::now();
    auto mesh =
        run.surfaces->reconstruct(run.sim.positionBuffer(), run.sim.liveParticleCount(), options);
    if (!mesh)
        return mesh.error();
    const auto built = std::chrono::steady_clock::now();
    auto written = writeSurfacePly(std::filesystem::path(o.surfaceDir) / surfaceName(step), *mesh);
    run.surfaceSeconds.push_back(std::chrono::duration<double>(built - start).count());
    run.surfaceStages.push_back(mesh->timings);
    run.surfaceVertices = mesh->vertices.size();
    run.surfaceTriangles = mesh->triangles.size();
    run.surfaceWriteSeconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - built).count());
    return written;
}

/// The median over the run's surface meshes of each reconstruction stage [ms].
nlohmann::json surfaceStageMedians(const HeadlessRun& run) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [name, member] : kSurfaceStages) {
        std::vector<double> values;
        for (const SurfaceTimings& t : run.surfaceStages)
            values.push_back(t.*member);
        out[name] = median(std::move(values));
    }
    return out;
}

/// The summary's line on --surface-mesh: what one mesh costs (reconstruction and download,
/// then the PLY file) and where the time went, the medians over the run's meshes.
void printSurfaceTimes(const HeadlessRun& run) {
    if (run.surfaceSeconds.empty())
        return;
    const double build = median(run.surfaceSeconds);
    std::cout << "surface meshes: " << run.surfaceSeconds.size() << ", median " << build * 1e3
              << " ms each to reconstruct and download ("
              << (build > 0.0 ? double(run.sim.particleCount()) / build * 1e-6 : 0.0)
              << " M particles/s), " << median(run.surfaceWriteSeconds) * 1e3
              << " ms to write; the last " << run.surfaceVertices << " vertices, "
              << run.surfaceTriangles << " triangles\n  surface stages, median ms:";
    const nlohmann::json stages = surfaceStageMedians(run);
    for (const auto& stage : kSurfaceStages)
        std::cout << "  " << stage.first << " " << stages[stage.first].get<double>();
    std::cout << "\n";
}

std::string bodiesName(std::uint64_t step) {
    char name[40];
    std::snprintf(name, sizeof name, "frame_%06llu.bodies.json",
                  static_cast<unsigned long long>(step));
    return name;
}

/// The PLY file (and, with dynamic bodies, their transforms beside it), the surface mesh and
/// the captured frame of step `step`, where they are due.
Result<void> writeStepOutputs(HeadlessRun& run, std::uint64_t step) {
    const HeadlessOptions& o = run.options;
    if (!o.plyDir.empty() && step % o.dumpEvery == 0) {
        const auto particles = run.sim.downloadParticles();
        if (auto ok = writePly(std::filesystem::path(o.plyDir) / plyName(step), particles,
                               run.sim.constants().radius);
            !ok)
            return ok;
        const std::vector<BodyState> bodies = run.sim.bodies();
        if (!bodies.empty()) {
            const std::string text =
                bodyTransformsJson(run.scene, step, run.sim.time(), bodies).dump(2) + "\n";
            if (auto ok =
                    format::writeFileAtomic(std::filesystem::path(o.plyDir) / bodiesName(step),
                                            std::as_bytes(std::span(text.data(), text.size())));
                !ok)
                return ok;
        }
    }
    if (auto ok = writeSurface(run, step); !ok)
        return ok;
    return run.capture ? run.capture->afterStep(run.sim, step) : Result<void>{};
}

/// A statistics row of step `step` (printed and kept for the JSON file, with the bodies' row of
/// --bodies-csv), where one is due; `last`: the run's last step, always recorded.
void recordStats(HeadlessRun& run, std::uint64_t step, bool last) {
    if (step % run.statsEvery != 0 && !last)
        return;
    const StepStats stats = run.sim.readStats();
    double gpuMs = 0.0;
    for (double t : run.sim.passTimes())
        gpuMs += t > 0.0 ? t : 0.0;
    if (!run.options.quiet) {
        run.progress.clear();
        // Flushed row by row, so a pipe (tee, a CI log) shows the run as it goes.
        std::cout << statsTableRow(stats, gpuMs > 0.0 ? gpuMs : -1.0) << std::flush;
    }
    nlohmann::json row = statsJson(stats);
    const std::vector<BodyState> bodies = run.sim.bodies();
    if (!bodies.empty())
        row["bodies"] = bodiesJson(bodies);
    run.bodiesCsv.record(run.scene, step, run.sim.time(), bodies);
    run.steps.push_back(std::move(row));
    if (stats.nonFinite > 0) {
        run.progress.clear();
        std::cerr << "sluice-play: step " << stats.step << ": " << stats.nonFinite
                  << " particles went non-finite and were reset to their last position\n";
        run.dirty = true;
    }
    if (stats.insideColliders > 0)
        run.dirty = true;
    if (stats.bodyFaults > 0 && run.bodyFaults == 0)
        std::cerr << "sluice-play: step " << stats.step
                  << ": a dynamic body went non-finite or its centre left the domain box, and "
                     "was put back at rest (a body the solver lost: check its density or "
                     "mass); \"bodyFaults\" in the statistics counts every time\n";
    if (stats.bodyFaults > run.bodyFaults) {
        run.bodyFaults = stats.bodyFaults;
        run.dirty = true;
    }
}

/// Says once that the emitters ran out of capacity (a cheap CPU-side flag).
void reportCapacity(HeadlessRun& run, std::uint64_t step) {
    if (run.capacityReported || run.scene.emitters.empty() ||
        run.sim.particleCount() != run.sim.capacity())
        return;
    std::cerr << "sluice-play: step " << step << ": particle capacity " << run.sim.capacity()
              << " reached; emitters stop adding particles\n";
    run.capacityReported = true;
}

/// Steps 1..steps with their statistics and outputs; step 0's outputs first. A SIGINT or
/// SIGTERM (InterruptGuard) ends the loop after the current step, whose statistics are then
/// recorded as the last.
Result<void> runSteps(HeadlessRun& run) {
    if (auto ok = writeStepOutputs(run, 0); !ok)
        return ok;
    run.bodiesCsv.record(run.scene, 0, run.sim.time(), run.sim.bodies());
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t step = 1; step <= run.options.steps && !InterruptGuard::requested();
         ++step) {
        run.sim.step();
        run.stepsDone = step;
        recordStats(run, step, step == run.options.steps || InterruptGuard::requested());
        if (auto ok = writeStepOutputs(run, step); !ok)
            return ok;
        reportCapacity(run, step);
        run.progress.update(step);
    }
    run.progress.clear();
    if (run.capture) {
        if (auto ok = run.capture->finish(); !ok)
            return ok;
    }
    glFinish();
    run.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.passTimes = run.sim.passTimes();
    return {};
}

/// A signal ended the run before its last step.
bool interrupted(const HeadlessRun& run) {
    return InterruptGuard::requested() && run.stepsDone < run.options.steps;
}

double stepsPerSecond(const HeadlessRun& run) {
    return run.wallSeconds > 0.0 ? double(run.stepsDone) / run.wallSeconds : 0.0;
}

void printSummary(const HeadlessRun& run) {
    const PassTimes& times = run.passTimes;
    std::cout << "\n"
              << run.stepsDone << " steps in " << run.wallSeconds
              << " s wall: " << stepsPerSecond(run) << " steps/s (" << run.context.info().renderer
              << ")\nGPU ms per step:";
    for (std::size_t p = 0; p < times.size(); ++p)
        if (times[p] >= 0.0)
            std::cout << "  " << passName(Pass(p)) << " " << times[p];
    std::cout << "\n";
    printSurfaceTimes(run);
    if (run.capture)
        run.capture->report(std::cout);
}

Result<void> writeStatsFile(HeadlessRun& run) {
    const HeadlessOptions& o = run.options;
    nlohmann::json doc = {
        {"tool", std::string("sluice-play ") + SLUICE_VERSION},
        {"scene", run.scene.path},
        {"name", run.scene.name},
        {"deterministic", o.deterministic},
        {"parameters", parametersJson(run.scene.simulation, run.sim.constants())},
        {"capacity", run.sim.capacity()},
        {"steps", run.steps},
    };
    if (interrupted(run))
        doc["interrupted"] = {{"signal", InterruptGuard::signalName()},
                              {"afterStep", run.stepsDone},
                              {"ofSteps", o.steps}};
    // Timings differ run to run; a deterministic run leaves them out so its file is
    // byte-identical every time.
    if (!o.deterministic)
        doc["timing"] = {{"renderer", run.context.info().renderer},
                         {"wallSeconds", run.wallSeconds},
                         {"stepsPerSecond", stepsPerSecond(run)},
                         {"gpuMsPerStep", passTimesJson(run.passTimes)}};
    if (!o.deterministic && !run.surfaceSeconds.empty())
        doc["timing"]["surfaceMeshMs"] = {{"count", run.surfaceSeconds.size()},
                                          {"median", median(run.surfaceSeconds) * 1e3},
                                          {"writeMedian", median(run.surfaceWriteSeconds) * 1e3},
                                          {"stagesMedian", surfaceStageMedians(run)}};
    const std::string text = doc.dump(2) + "\n";
    return format::writeFileAtomic(o.statsJson, std::as_bytes(std::span(text.data(), text.size())));
}

/// Before the first step: a run a software renderer would take minutes over is said so.
void warnIfSlow(const HeadlessRun& run) {
    const auto warning = slowRunWarning(run.context.info().renderer, run.sim.capacity(),
                                        run.scene.simulation.substeps, run.options.steps,
                                        std::thread::hardware_concurrency());
    if (warning)
        std::cerr << "sluice-play: warning [slow-run]: " << *warning << '\n';
}

/// The files of the run, written when it ends, however it ends.
Result<void> writeEndOutputs(HeadlessRun& run) {
    if (!run.options.statsJson.empty())
        if (auto ok = writeStatsFile(run); !ok)
            return ok;
    return run.bodiesCsv.write();
}

int interruptedExit(const HeadlessRun& run) {
    std::cerr << "sluice-play: " << InterruptGuard::signalName() << ": stopped after step "
              << run.stepsDone << " of " << run.options.steps
              << "; the outputs asked for were written up to it\n";
    return InterruptGuard::exitCode();
}

} // namespace

int playHeadless(const HeadlessOptions& o, const format::Scene& scene,
                 std::vector<format::ColliderAsset> colliders) {
    const InterruptGuard interrupt;
    const std::vector<std::string> colliderLines = describeColliders(scene, colliders);
    auto context = gpu::Context::createHeadless();
    if (!context)
        return reportFailure(context.error());
    auto run = startRun(o, scene, std::move(colliders), *context);
    if (!run)
        return reportFailure(run.error());
    if (!o.quiet)
        printStartup(*run, colliderLines);
    warnIfSlow(*run);
    if (auto ok = runSteps(*run); !ok)
        return reportFailure(ok.error());
    if (!o.quiet)
        printSummary(*run);
    if (auto ok = writeEndOutputs(*run); !ok)
        return reportFailure(ok.error());
    if (interrupted(*run))
        return interruptedExit(*run);
    if (o.check && run->dirty) {
        std::cerr << "sluice-play: --check: particles went non-finite or ended inside a "
                     "collider, or a body was lost (see the messages above and the table)\n";
        return kExitCheckFailed;
    }
    return kExitOk;
}

} // namespace sluice::rt
