// The benchmark loop: warm-up, then one GPU-timed step at a time, medians over the steps.
#include "play/Bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "output/StatsReport.h"
#include "play/SceneChecks.h"
#include "shared/Pbf.h"
#include "sluice/format/support/AtomicFile.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/play/PlayCli.h"
#include "sluice/rt/render/SceneFraming.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

/// Prints the median of every pass's times under a `title` column and returns them as a JSON
/// object keyed by `nameOf(pass index)`.
template <typename NameOf>
nlohmann::json printMedians(const char* title, const std::vector<std::vector<double>>& passMs,
                            NameOf nameOf) {
    std::printf("  %-16s %12s\n", title, "median ms");
    nlohmann::json medians = nlohmann::json::object();
    for (std::size_t p = 0; p < passMs.size(); ++p) {
        const double m = median(passMs[p]);
        std::printf("  %-16s %12.4f\n", nameOf(p), m);
        medians[nameOf(p)] = m;
    }
    return medians;
}

/// Renders the simulation's current state o.renderFrames times after a few unmeasured frames,
/// waiting for each frame, so that every frame's GPU timers are its own; prints the medians
/// and returns them as JSON.
nlohmann::json benchRender(Renderer& renderer, const format::Scene& scene, const Simulation& sim,
                           const BenchOptions& o, const std::string& glRenderer) {
    OrbitCamera camera =
        sceneCamera(scene, renderer.bounds(), float(o.renderSize.x) / float(o.renderSize.y));
    camera.zoom(o.zoom);
    constexpr int kWarmupFrames = 3;
    for (int i = 0; i < kWarmupFrames; ++i)
        renderer.render(sim, camera, o.render);
    glFinish();
    (void)renderer.gpuMilliseconds();
    (void)renderer.passTimes();
    std::vector<double> frameMs;
    std::vector<std::vector<double>> passMs(std::size_t(RenderPass::Count));
    const auto start = std::chrono::steady_clock::now();
    for (std::uint32_t i = 0; i < o.renderFrames; ++i) {
        renderer.render(sim, camera, o.render);
        glFinish(); // the frame's queries are complete: the latest times are this frame's
        frameMs.push_back(renderer.gpuMilliseconds().value_or(-1.0));
        const RenderPassTimes times = renderer.passTimes();
        for (std::size_t p = 0; p < times.size(); ++p)
            passMs[p].push_back(times[p]);
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("  render %ux%u, %s, %u particles, %u frames (each waited for):\n", o.renderSize.x,
                o.renderSize.y, std::string(surfaceModeName(o.render.surface)).c_str(),
                sim.particleCount(), o.renderFrames);
    // The frame's passes, then the screen-space surface's stages (parts of "fluid", timed in
    // that mode only).
    const auto stagesBegin = passMs.begin() + std::ptrdiff_t(RenderPass::FluidSpheres);
    const std::vector<std::vector<double>> framePasses(passMs.begin(), stagesBegin);
    const nlohmann::json passes = printMedians(
        "render pass", framePasses, [](std::size_t p) { return renderPassName(RenderPass(p)); });
    nlohmann::json stages = nullptr;
    if (o.render.surface == SurfaceMode::Fluid)
        stages = printMedians("  fluid stage", std::vector(stagesBegin, passMs.end()),
                              [](std::size_t p) {
                                  return renderPassName(
                                      RenderPass(p + std::size_t(RenderPass::FluidSpheres)));
                              });
    const double frame = median(frameMs);
    std::printf("  %-16s %12.4f   (wall %.4f ms per frame, glFinish included)\n", "frame", frame,
                1e3 * wall / double(o.renderFrames));
    // Mesa's software rasterizers bin the draws and rasterize them when something later
    // flushes them, so a draw's time lands in a later pass's timer or in none (a frame of
    // spheres reads near 0); compute dispatches are timed right.
    const bool softwareRaster = glRenderer.find("llvmpipe") != std::string::npos ||
                                glRenderer.find("softpipe") != std::string::npos;
    if (softwareRaster)
        std::printf("  note: %s rasterizes when a later command flushes the draws, so its render "
                    "timers miss or misplace them; read the wall time per frame\n",
                    glRenderer.c_str());
    return {{"width", o.renderSize.x},
            {"height", o.renderSize.y},
            {"surface", std::string(surfaceModeName(o.render.surface))},
            {"colour", std::string(colourModeName(o.render.colour))},
            {"zoom", o.zoom},
            {"frames", o.renderFrames},
            {"medianFrameMs", frame},
            {"medianPassMs", passes},
            {"medianFluidStageMs", stages},
            {"wallMsPerFrame", 1e3 * wall / double(o.renderFrames)},
            {"gpuTimersCoverDrawing", !softwareRaster}};
}

/// What the measured steps gave.
struct StepFigures {
    std::vector<double> stepMs;              ///< GPU time of each measured step [ms]
    std::vector<std::vector<double>> passMs; ///< per pass, each measured step [ms]
    std::uint64_t iterations = 0;            ///< solver iterations of last substeps, summed
    double meanIterationsSum = 0.0;          ///< each step's iterations per substep, summed
    double errorSum = 0.0;                   ///< average density errors, summed
    double wallSeconds = 0.0;                ///< the measured steps, without per-step waits
    std::uint64_t maskOverflow = 0;          ///< particle-substeps past the neighbour mask
    std::uint32_t maxCandidates = 0;         ///< most candidates of one particle
    std::uint32_t maxNeighbours = 0;         ///< most neighbours of one particle
    GpuCommandCount commands;                ///< queued by the measured steps
    std::uint64_t solveDispatchesRun = 0;    ///< lambda and delta dispatches that launched groups
};

/// The renderer of --bench-frames, created before the solver takes the colliders (it uploads
/// them to 3D textures of its own); none when no frames are asked for.
Result<std::optional<Renderer>>
createRenderer(const BenchOptions& o, const format::Scene& scene,
               const std::vector<format::ColliderAsset>& colliders) {
    if (o.renderFrames == 0)
        return std::optional<Renderer>{};
    auto created = Renderer::create(scene, colliders, o.renderSize);
    if (!created)
        return created.error();
    return std::optional<Renderer>(std::move(*created));
}

/// Warm-up steps, then the measured ones. Each measured step is drained before the next, so
/// the GPU times are per step; the wall time of the whole run is measured separately, without
/// per-step waits.
StepFigures measureSteps(Simulation& sim, const BenchOptions& o) {
    for (std::uint64_t i = 0; i < o.warmup; ++i)
        sim.step();
    sim.drainPassTimes();
    StepFigures f;
    f.passMs.resize(std::size_t(Pass::Count));
    const GpuCommandCount before = sim.commandCount();
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t i = 0; i < o.steps; ++i) {
        sim.step();
        const PassTimes times = sim.drainPassTimes();
        double total = 0.0;
        for (std::size_t p = 0; p < times.size(); ++p) {
            f.passMs[p].push_back(times[p]);
            total += std::max(times[p], 0.0);
        }
        f.stepMs.push_back(total);
        const StepStats stats = sim.readStats();
        f.iterations += stats.iterations;
        f.meanIterationsSum += stats.meanIterations;
        f.errorSum += stats.avgDensityError;
        f.maskOverflow += stats.maskOverflow;
        f.maxCandidates = std::max(f.maxCandidates, stats.maxCandidates);
        f.maxNeighbours = std::max(f.maxNeighbours, stats.maxNeighbours);
        f.solveDispatchesRun += stats.solveDispatches;
    }
    f.commands = sim.commandCount() - before;
    f.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return f;
}

/// The figures derived from the measured steps, as printed and written.
struct StepSummary {
    std::uint32_t particles = 0;
    double stepMedian = 0.0; ///< [ms]
    double substeps = 0.0;
    double avgIterations = 0.0; ///< iterations per substep, mean over every measured substep
    double lastSubstepIterations = 0.0; ///< mean iterations of each step's last substep
    double avgError = 0.0;              ///< mean average density error
    double throughput = 0.0;            ///< particle-iterations per second of median GPU step time
    double stepsPerSecondWall = 0.0;
    std::string grid; ///< "dense 50x25x10 cells" or "hash"
    std::uint64_t maskOverflow = 0;
    std::uint32_t maxCandidates = 0;
    std::uint32_t maxNeighbours = 0;
    double dispatchesPerSubstep = 0.0;    ///< issued, the step statistics' share included
    double dispatchesRunPerSubstep = 0.0; ///< of them, the ones that launched work groups
    double barriersPerSubstep = 0.0;
};

StepSummary summarize(const Simulation& sim, const format::Scene& scene, const BenchOptions& o,
                      const StepFigures& f) {
    StepSummary s;
    const double steps = double(std::max<std::uint64_t>(o.steps, 1));
    s.particles = sim.particleCount();
    s.stepMedian = median(f.stepMs);
    s.substeps = scene.simulation.substeps;
    s.avgIterations = f.meanIterationsSum / steps;
    s.lastSubstepIterations = double(f.iterations) / steps;
    s.avgError = f.errorSum / steps;
    // Particle-iterations per second: particles x substeps x iterations per substep, per
    // second of median GPU step time.
    s.throughput = s.stepMedian > 0.0
                       ? s.particles * s.substeps * s.avgIterations / (s.stepMedian * 1e-3)
                       : 0.0;
    s.stepsPerSecondWall = f.wallSeconds > 0 ? double(o.steps) / f.wallSeconds : 0.0;
    s.maskOverflow = f.maskOverflow;
    s.maxCandidates = f.maxCandidates;
    s.maxNeighbours = f.maxNeighbours;
    // Per substep, the step statistics' pass spread over the substeps. An idle indirect solve
    // dispatch is issued and counted, but launches nothing; the GPU counts the ones that ran.
    const double substepsMeasured = steps * std::max(1.0, s.substeps);
    s.dispatchesPerSubstep = double(f.commands.dispatches) / substepsMeasured;
    s.barriersPerSubstep = double(f.commands.barriers) / substepsMeasured;
    const double idle = double(f.commands.indirect) - double(f.solveDispatchesRun);
    s.dispatchesRunPerSubstep = (double(f.commands.dispatches) - std::max(idle, 0.0)) /
                                substepsMeasured;
    const glm::uvec3 grid = sim.neighbourGridCells();
    s.grid = grid.x > 0 ? "dense " + std::to_string(grid.x) + "x" + std::to_string(grid.y) + "x" +
                              std::to_string(grid.z) + " cells"
                        : std::string("hash");
    return s;
}

/// Prints the step table; returns the per-pass medians as JSON.
nlohmann::json printSteps(const Simulation& sim, const format::Scene& scene,
                          const std::string& glRenderer, const std::vector<std::string>& colliders,
                          const StepFigures& f, const StepSummary& s) {
    std::printf("sluice-play --bench %s\n", scene.path.c_str());
    for (const std::string& line : colliders)
        std::printf("  %s\n", line.c_str());
    std::printf("  GL: %s\n  %u particles, %g substeps, %.2f iterations "
                "(mean of every measured substep), avg density error %.3f %%\n",
                glRenderer.c_str(), s.particles, s.substeps, s.avgIterations, 100.0 * s.avgError);
    const nlohmann::json passes =
        printMedians("pass", f.passMs, [](std::size_t p) { return passName(Pass(p)); });
    std::printf("  %-16s %12.4f\n  steps/s (GPU median): %.2f   steps/s (wall): %.2f\n"
                "  particle-iterations/s: %.4g   GPU memory: %llu bytes (%llu per particle of "
                "capacity, hash table and neighbour mask included, colliders not)\n",
                "step", s.stepMedian, s.stepMedian > 0 ? 1e3 / s.stepMedian : 0.0,
                s.stepsPerSecondWall, s.throughput, static_cast<unsigned long long>(sim.gpuBytes()),
                static_cast<unsigned long long>(sim.bytesPerParticle()));
    std::printf("  GPU commands per substep: %.2f dispatches (%.2f launched work; the rest are "
                "solver iterations after the early stop), %.2f memory barriers\n",
                s.dispatchesPerSubstep, s.dispatchesRunPerSubstep, s.barriersPerSubstep);
    std::printf("  neighbour grid: %s; %u invocations per particle in the neighbour passes\n",
                s.grid.c_str(), sim.neighbourLanes());
    std::printf("  neighbour mask: %u bits per particle; most candidates %u, most neighbours %u; "
                "%llu particle-substeps past the mask (tested in full)\n",
                shared::kNeighbourMaskBits, s.maxCandidates, s.maxNeighbours,
                static_cast<unsigned long long>(s.maskOverflow));
    return passes;
}

Result<void> writeBenchJson(const BenchOptions& o, const format::Scene& scene,
                            const std::string& glRenderer, const Simulation& sim,
                            const StepSummary& s, const nlohmann::json& passes,
                            const nlohmann::json& render) {
    nlohmann::json doc = {
        {"tool", std::string("sluice-play ") + SLUICE_VERSION},
        {"scene", scene.path},
        {"renderer", glRenderer},
        {"particles", s.particles},
        {"substeps", s.substeps},
        {"meanIterations", s.avgIterations},
        {"meanIterationsLastSubstep", s.lastSubstepIterations},
        {"avgDensityError", s.avgError},
        {"warmupSteps", o.warmup},
        {"measuredSteps", o.steps},
        {"medianStepMs", s.stepMedian},
        {"medianPassMs", passes},
        {"stepsPerSecondGpu", s.stepMedian > 0 ? 1e3 / s.stepMedian : 0.0},
        {"stepsPerSecondWall", s.stepsPerSecondWall},
        {"particleIterationsPerSecond", s.throughput},
        {"gpuBytes", sim.gpuBytes()},
        {"bytesPerParticle", sim.bytesPerParticle()},
        {"neighbourGrid", s.grid},
        {"neighbourLanes", sim.neighbourLanes()},
        {"computeSmallSpheres", o.render.computeSmallSpheres},
        {"neighbourMaskBits", shared::kNeighbourMaskBits},
        {"maskOverflow", s.maskOverflow},
        {"maxCandidates", s.maxCandidates},
        {"maxNeighbours", s.maxNeighbours},
        {"dispatchesPerSubstep", s.dispatchesPerSubstep},
        {"dispatchesRunPerSubstep", s.dispatchesRunPerSubstep},
        {"barriersPerSubstep", s.barriersPerSubstep},
    };
    if (!render.is_null())
        doc["render"] = render;
    const std::string text = doc.dump(2) + "\n";
    return format::writeFileAtomic(o.json, std::as_bytes(std::span(text.data(), text.size())));
}

} // namespace

int runBench(const BenchOptions& o, const format::Scene& scene,
             std::vector<format::ColliderAsset> colliders) {
    const std::vector<std::string> colliderLines = describeColliders(scene, colliders);
    auto context = gpu::Context::createHeadless();
    if (!context)
        return reportFailure(context.error());
    auto renderer = createRenderer(o, scene, colliders);
    if (!renderer)
        return reportFailure(renderer.error());
    SimulationOptions options;
    options.deterministic = o.deterministic;
    options.timers = true;
    options.neighbourLanes = o.neighbourLanes;
    auto sim = Simulation::create(scene, std::move(colliders), options);
    if (!sim)
        return reportFailure(sim.error());

    const std::string& glRenderer = context->info().renderer;
    const StepFigures figures = measureSteps(*sim, o);
    const StepSummary summary = summarize(*sim, scene, o, figures);
    const nlohmann::json passes =
        printSteps(*sim, scene, glRenderer, colliderLines, figures, summary);
    nlohmann::json render = nullptr;
    if (*renderer)
        render = benchRender(**renderer, scene, *sim, o, glRenderer);
    if (!o.json.empty())
        if (auto ok = writeBenchJson(o, scene, glRenderer, *sim, summary, passes, render); !ok)
            return reportFailure(ok.error());
    return kExitOk;
}

} // namespace sluice::rt
