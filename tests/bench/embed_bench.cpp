// What the calls a game makes every frame cost beside the step itself (docs/embedding.md): a
// collider pose set, the particle view taken and the bodies' forces read without waiting.
//
//   embed_bench COLLIDER.slc [--particles N] [--frames F] [--repeat R] [--control 1]
//               [--measure 1]
//
// A scene built in code: a block of N particles (default 5000) in a tank, COLLIDER as a static
// collider the game moves and again as a dynamic body the water floats. Frames alternate between
// "step only" (step(), then glFinish so the GPU's work counts) and "step + calls"
// (setColliderPose to where it is, step(), particleView, latestBodies, then glFinish), F frames
// of each per repeat (default 20), R repeats (default 5). It prints the median and range over
// the repeats of each kind's mean frame time, their ratio, and the calls' own CPU time per frame,
// each call timed alone. --control 1 makes no call in the second kind of frame either: the ratio
// the machine's noise alone gives (an A/A run). --measure 1 also measures the moved collider's
// force in the second kind of frame (measureForce on before the step, latestForces after it,
// off again after the frame): the ratio is then what the measurement's GPU work adds. Not a
// ctest test. Say where it ran (llvmpipe on a CPU is not a GPU).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "BenchFigures.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/gpu/Context.h"
#include "sluice/gpu/Gl.h"
#include "sluice/rt/sim/Simulation.h"

namespace {

using namespace sluice;
using Clock = std::chrono::steady_clock;

using bench::Figures;
using bench::figures;

double since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// A cube block of about `particles` particles at 2 cm in a tank twice as wide, the collider
// standing in it and floating on it.
format::Scene benchScene(std::uint32_t particles, const std::string& collider) {
    const int side = int(std::cbrt(double(particles)));
    const float s = 0.02f;
    format::Scene scene;
    scene.path = "embed_bench";
    format::FluidBlock block;
    block.max = glm::vec3(float(side) * s);
    scene.blocks.push_back(block);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(2.0f * side * s, 1.5f * side * s, float(side) * s);
    scene.simulation.substeps = 2;
    format::SceneCollider moved;
    moved.asset = collider;
    moved.scale = 0.2f;
    moved.translation = glm::vec3(1.5f * side * s, 0.05f, 0.5f * side * s);
    scene.colliders.push_back(moved);
    format::SceneCollider floating = moved;
    floating.translation = glm::vec3(1.5f * side * s, 0.6f * side * s, 0.5f * side * s);
    floating.dynamic = format::DynamicBody{.density = 500.0f};
    scene.colliders.push_back(floating);
    return scene;
}

int usage(const char* why) {
    std::fprintf(stderr,
                 "embed_bench: %s\nusage: embed_bench COLLIDER.slc [--particles N] [--frames F] "
                 "[--repeat R] [--control 1] [--measure 1]\n",
                 why);
    return 2;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2)
        return usage("no collider given");
    std::uint32_t particles = 5000, frames = 20, repeat = 5, control = 0, measure = 0;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::uint32_t value = std::uint32_t(std::strtoul(argv[i + 1], nullptr, 10));
        if (std::strcmp(argv[i], "--particles") == 0)
            particles = value;
        else if (std::strcmp(argv[i], "--frames") == 0)
            frames = value;
        else if (std::strcmp(argv[i], "--repeat") == 0)
            repeat = value;
        else if (std::strcmp(argv[i], "--control") == 0)
            control = value;
        else if (std::strcmp(argv[i], "--measure") == 0)
            measure = value;
        else
            return usage(argv[i]);
    }
    auto context = gpu::Context::createHeadless();
    if (!context)
        return usage(context.error().message().c_str());
    const format::Scene scene = benchScene(particles, argv[1]);
    auto assets = rt::loadSceneColliders(scene);
    if (!assets)
        return usage(assets.error().message().c_str());
    auto sim = rt::Simulation::create(scene, std::move(*assets));
    if (!sim)
        return usage(sim.error().message().c_str());
    std::printf("%s; %u particles, %u substeps\n", context->info().renderer.c_str(),
                sim->particleCount(), sim->parameters().substeps);
    for (int i = 0; i < 5; ++i) // warm-up: shader caches, first volume map reads
        sim->step();
    // The pose the collider has: the call's whole cost (the record is uploaded on every
    // substep of the next step), without a motion that would change the solver's work.
    const glm::vec3 at = scene.colliders[0].translation;
    std::vector<double> plain, embedded, calls;
    for (std::uint32_t r = 0; r < repeat; ++r) {
        double plainMs = 0.0, embeddedMs = 0.0, callMs = 0.0;
        for (std::uint32_t f = 0; f < frames; ++f) {
            auto t0 = Clock::now();
            sim->step();
            glFinish();
            plainMs += since(t0);

            t0 = Clock::now();
            auto tc = Clock::now();
            if (control == 0)
                (void)sim->setColliderPose(0, at, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
            if (measure != 0)
                (void)sim->measureForce(0, true);
            callMs += since(tc);
            sim->step();
            tc = Clock::now();
            if (control == 0) {
                const rt::ParticleView view = sim->particleView();
                const auto forces = sim->latestBodies();
                if (view.count == 0 || (forces && forces->bodies.empty()))
                    return usage("no particles or no body");
            }
            if (measure != 0 && sim->latestForces() && sim->latestForces()->colliders.empty())
                return usage("no force measured");
            callMs += since(tc);
            glFinish();
            embeddedMs += since(t0);
            if (measure != 0)
                (void)sim->measureForce(0, false);
        }
        plain.push_back(plainMs / frames);
        embedded.push_back(embeddedMs / frames);
        calls.push_back(callMs / frames);
    }
    const Figures p = figures(plain), e = figures(embedded), c = figures(calls);
    std::printf("step only      %9.3f ms (%.3f - %.3f)\n", p.median, p.lo, p.hi);
    std::printf("step + calls   %9.3f ms (%.3f - %.3f)\n", e.median, e.lo, e.hi);
    std::printf("ratio          %9.4f\n", e.median / p.median);
    std::printf("calls' own CPU %9.4f ms (%.4f - %.4f), %.3f %% of the step\n", c.median, c.lo,
                c.hi, 100.0 * c.median / p.median);
    return 0;
}
