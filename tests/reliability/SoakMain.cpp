// sluice_soak: plays a scene for many steps and checks every step: no particle goes non-finite,
// none ends inside a collider, and memory stays flat. Run by soak.sh (docs/reliability.md);
// not a ctest case (100,000 steps take tens of minutes on llvmpipe).
//
//   sluice_soak SCENE.json [--steps N] [--report-every K]
//
// Every step reads the solver's own statistics (non-finite resets, particles inside
// colliders); every K steps it also downloads the particles and checks them on the CPU
// (finite, and phi >= -r/2 in every collider by the CPU sampler at the collider's pose), and
// prints a row with its resident memory (VmRSS). Exit 0 if every check held, 1 if one failed,
// 2 for bad input, 3 without an OpenGL 4.5 context.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "sluice/format/scene/SceneIO.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/sim/SceneSetup.h"
#include "sluice/rt/sim/Simulation.h"

namespace {

using namespace sluice;

/// [kB] this process's resident memory, from /proc/self/status; -1 if unknown.
long residentKb() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0)
            return std::strtol(line.c_str() + 6, nullptr, 10);
    return -1;
}

int fail(const Error& error) {
    std::fprintf(stderr, "sluice_soak: %s\n", error.message().c_str());
    return error.code == ErrorCode::NoGlContext ? 3 : 2;
}

struct CpuCheck {
    std::uint64_t nonFinite = 0;
    std::uint64_t inside = 0;
    double worstPhi = 0.0; ///< [m] most negative phi + r/2 seen (0 if none inside)
};

CpuCheck checkOnCpu(const rt::Simulation& sim, const std::vector<format::SdfSampler>& samplers,
                    double time) {
    CpuCheck out;
    const format::Scene& scene = sim.scene();
    const double halfRadius = 0.5 * sim.constants().radius;
    std::vector<rt::ColliderPose> poses;
    for (const format::SceneCollider& c : scene.colliders)
        poses.push_back(rt::colliderPose(c, float(time)));
    for (const rt::ParticleState& p : sim.downloadParticles()) {
        const glm::vec3 x = p.position, v = p.velocity;
        if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z) ||
            !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
            ++out.nonFinite;
            continue;
        }
        for (std::size_t c = 0; c < samplers.size(); ++c) {
            const glm::vec3 local = poses[c].toLocal(x);
            const double phi = double(samplers[c].value(glm::dvec3(local))) * poses[c].scale;
            if (phi < -halfRadius) {
                ++out.inside;
                out.worstPhi = std::min(out.worstPhi, phi + halfRadius);
                break;
            }
        }
    }
    return out;
}

} // namespace

int main(int argc, char** argv) {
    std::string scenePath;
    std::uint64_t steps = 100'000, every = 1000;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--steps" && i + 1 < argc)
            steps = std::strtoull(argv[++i], nullptr, 10);
        else if (arg == "--report-every" && i + 1 < argc)
            every = std::strtoull(argv[++i], nullptr, 10);
        else if (scenePath.empty() && arg[0] != '-')
            scenePath = arg;
        else {
            std::fprintf(stderr, "usage: sluice_soak SCENE.json [--steps N] [--report-every K]\n");
            return 2;
        }
    }
    if (scenePath.empty() || steps == 0 || every == 0) {
        std::fprintf(stderr, "usage: sluice_soak SCENE.json [--steps N] [--report-every K]\n");
        return 2;
    }

    auto scene = format::readScene(scenePath);
    if (!scene)
        return fail(scene.error());
    auto colliders = rt::loadSceneColliders(*scene);
    if (!colliders)
        return fail(colliders.error());
    // The CPU check samples the same grids the GPU does.
    const std::vector<format::ColliderAsset> assets = *colliders;
    std::vector<format::SdfSampler> samplers;
    for (const format::ColliderAsset& a : assets)
        samplers.emplace_back(a);
    auto context = gpu::Context::createHeadless();
    if (!context)
        return fail(context.error());
    rt::SimulationOptions options;
    options.timers = false; // nothing reads them; the soak measures the solver, not the queries
    auto sim = rt::Simulation::create(*scene, std::move(*colliders), options);
    if (!sim)
        return fail(sim.error());

    std::printf("soak %s: %u particles (capacity %u), %zu colliders, %u substeps, %llu steps, "
                "GL %s\n",
                scenePath.c_str(), sim->particleCount(), sim->capacity(), assets.size(),
                scene->simulation.substeps, static_cast<unsigned long long>(steps),
                context->info().renderer.c_str());
    std::printf("%10s %10s %9s %10s %10s %9s %9s %10s %9s\n", "step", "time s", "particles",
                "maxSpeed", "avgErr %", "nonFinite", "inside", "cpuInside", "rss kB");
    std::fflush(stdout);

    std::uint64_t nonFiniteTotal = 0, firstNonFiniteStep = 0, insideSteps = 0, firstInsideStep = 0,
                  cpuNonFinite = 0, cpuInside = 0;
    std::uint32_t maxInside = 0;
    long rssFirst = -1, rssLast = -1, rssMax = -1;
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t step = 1; step <= steps; ++step) {
        sim->step();
        const rt::StepStats stats = sim->readStats();
        if (stats.nonFinite > 0) {
            nonFiniteTotal += stats.nonFinite;
            if (firstNonFiniteStep == 0)
                firstNonFiniteStep = step;
            std::printf("step %llu: %u particles went non-finite and were reset\n",
                        static_cast<unsigned long long>(step), stats.nonFinite);
        }
        if (stats.insideColliders > 0) {
            ++insideSteps;
            maxInside = std::max(maxInside, stats.insideColliders);
            if (firstInsideStep == 0)
                firstInsideStep = step;
        }
        if (step % every == 0 || step == steps) {
            const CpuCheck cpu = checkOnCpu(*sim, samplers, stats.time);
            cpuNonFinite += cpu.nonFinite;
            cpuInside += cpu.inside;
            const long rss = residentKb();
            if (rssFirst < 0)
                rssFirst = rss;
            rssLast = rss;
            rssMax = std::max(rssMax, rss);
            std::printf("%10llu %10.2f %9u %10.4f %10.4f %9u %9u %10llu %9ld\n",
                        static_cast<unsigned long long>(step), stats.time, stats.particles,
                        stats.maxSpeed, 100.0 * stats.avgDensityError, stats.nonFinite,
                        stats.insideColliders, static_cast<unsigned long long>(cpu.inside), rss);
            std::fflush(stdout);
        }
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const bool clean =
        nonFiniteTotal == 0 && insideSteps == 0 && cpuNonFinite == 0 && cpuInside == 0;
    std::printf("\nsoak: %llu steps in %.1f s (%.1f steps/s)\n",
                static_cast<unsigned long long>(steps), wall, double(steps) / wall);
    std::printf("soak: non-finite resets %llu (first at step %llu); steps with particles inside "
                "colliders %llu (first %llu, most %u); CPU check: %llu non-finite, %llu inside\n",
                static_cast<unsigned long long>(nonFiniteTotal),
                static_cast<unsigned long long>(firstNonFiniteStep),
                static_cast<unsigned long long>(insideSteps),
                static_cast<unsigned long long>(firstInsideStep), maxInside,
                static_cast<unsigned long long>(cpuNonFinite),
                static_cast<unsigned long long>(cpuInside));
    std::printf("soak: VmRSS %ld kB at the first report, %ld kB at the end, %ld kB at most\n",
                rssFirst, rssLast, rssMax);
    std::printf("soak: %s\n", clean ? "clean" : "FAILED");
    return clean ? 0 : 1;
}
