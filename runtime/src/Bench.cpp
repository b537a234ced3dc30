// The benchmark loop: warm-up, then one GPU-timed step at a time, medians over the steps.
#include "Bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sluice/format/AtomicFile.h"
#include "sluice/format/SceneIO.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/PlayCli.h"
#include "sluice/rt/Simulation.h"
#include "sluice/rt/render/SceneFraming.h"

namespace sluice::rt {
namespace {

double median(std::vector<double> values) {
    if (values.empty())
        return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

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

int fail(const Error& error) {
    std::cerr << "sluice-play: " << error.message() << '\n';
    return error.code == ErrorCode::NoGlContext ? kPlayExitNoGlContext : kPlayExitBadInput;
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
    const nlohmann::json passes = printMedians(
        "render pass", passMs, [](std::size_t p) { return renderPassName(RenderPass(p)); });
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
            {"wallMsPerFrame", 1e3 * wall / double(o.renderFrames)},
            {"gpuTimersCoverDrawing", !softwareRaster}};
}

} // namespace

int runBench(const BenchOptions& o) {
    auto scene = format::readScene(o.scene);
    if (!scene)
        return fail(scene.error());
    auto colliders = loadSceneColliders(*scene);
    if (!colliders)
        return fail(colliders.error());
    auto context = gpu::Context::createHeadless();
    if (!context)
        return fail(context.error());
    // The renderer uploads the colliders to 3D textures of its own before the solver takes them.
    std::optional<Renderer> renderer;
    if (o.renderFrames > 0) {
        auto created = Renderer::create(*scene, *colliders, o.renderSize);
        if (!created)
            return fail(created.error());
        renderer.emplace(std::move(*created));
    }
    SimulationOptions options;
    options.deterministic = o.deterministic;
    auto sim = Simulation::create(*scene, std::move(*colliders), options);
    if (!sim)
        return fail(sim.error());

    for (std::uint64_t i = 0; i < o.warmup; ++i)
        sim->step();
    sim->drainPassTimes();

    // Each measured step is drained before the next, so the GPU times are per step; the wall
    // time of the whole run is measured separately, without per-step waits.
    std::vector<double> stepMs;
    std::vector<std::vector<double>> passMs(std::size_t(Pass::Count));
    std::uint64_t iterations = 0;
    double errorSum = 0.0;
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t i = 0; i < o.steps; ++i) {
        sim->step();
        const PassTimes times = sim->drainPassTimes();
        double total = 0.0;
        for (std::size_t p = 0; p < times.size(); ++p) {
            passMs[p].push_back(times[p]);
            total += std::max(times[p], 0.0);
        }
        stepMs.push_back(total);
        const StepStats stats = sim->readStats();
        iterations += stats.iterations;
        errorSum += stats.avgDensityError;
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const std::uint32_t particles = sim->particleCount();
    const double stepMedian = median(stepMs);
    const double substeps = scene->simulation.substeps;
    const double avgIterations = double(iterations) / double(std::max<std::uint64_t>(o.steps, 1));
    // Particle-iterations per second: particles x substeps x iterations of the last substep,
    // per second of median GPU step time.
    const double throughput =
        stepMedian > 0.0 ? particles * substeps * avgIterations / (stepMedian * 1e-3) : 0.0;

    std::printf("sluice-play --bench %s\n  GL: %s\n  %u particles, %g substeps, %.2f iterations "
                "(mean of the last substeps), avg density error %.3f %%\n",
                scene->path.c_str(), context->info().renderer.c_str(), particles, substeps,
                avgIterations, 100.0 * errorSum / double(std::max<std::uint64_t>(o.steps, 1)));
    const nlohmann::json passes =
        printMedians("pass", passMs, [](std::size_t p) { return passName(Pass(p)); });
    std::printf("  %-16s %12.4f\n  steps/s (GPU median): %.2f   steps/s (wall): %.2f\n"
                "  particle-iterations/s: %.4g   GPU memory: %llu bytes (%llu per particle of "
                "capacity, hash table included, colliders not)\n",
                "step", stepMedian, stepMedian > 0 ? 1e3 / stepMedian : 0.0,
                wall > 0 ? double(o.steps) / wall : 0.0, throughput,
                static_cast<unsigned long long>(sim->gpuBytes()),
                static_cast<unsigned long long>(sim->bytesPerParticle()));
    const glm::uvec3 grid = sim->neighbourGridCells();
    const std::string gridText = grid.x > 0 ? "dense " + std::to_string(grid.x) + "x" +
                                                  std::to_string(grid.y) + "x" +
                                                  std::to_string(grid.z) + " cells"
                                            : std::string("hash");
    std::printf("  neighbour grid: %s\n", gridText.c_str());

    nlohmann::json render = nullptr;
    if (renderer)
        render = benchRender(*renderer, *scene, *sim, o, context->info().renderer);

    if (!o.json.empty()) {
        nlohmann::json doc = {
            {"tool", std::string("sluice-play ") + SLUICE_VERSION},
            {"scene", scene->path},
            {"renderer", context->info().renderer},
            {"particles", particles},
            {"substeps", substeps},
            {"meanIterations", avgIterations},
            {"avgDensityError", errorSum / double(std::max<std::uint64_t>(o.steps, 1))},
            {"warmupSteps", o.warmup},
            {"measuredSteps", o.steps},
            {"medianStepMs", stepMedian},
            {"medianPassMs", passes},
            {"stepsPerSecondGpu", stepMedian > 0 ? 1e3 / stepMedian : 0.0},
            {"stepsPerSecondWall", wall > 0 ? double(o.steps) / wall : 0.0},
            {"particleIterationsPerSecond", throughput},
            {"gpuBytes", sim->gpuBytes()},
            {"bytesPerParticle", sim->bytesPerParticle()},
            {"neighbourGrid", gridText},
        };
        if (!render.is_null())
            doc["render"] = render;
        const std::string text = doc.dump(2) + "\n";
        if (auto ok = format::writeFileAtomic(o.json, std::as_bytes(std::span(text.data(), text.size())));
            !ok)
            return fail(ok.error());
    }
    return kPlayExitOk;
}

} // namespace sluice::rt
