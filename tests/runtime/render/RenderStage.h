// What the renderer's tests share (RenderTest.cpp, RenderComputeSpheresTest.cpp): one scene
// with its simulation, renderer and camera, drawn at a small size, and a block of water.
#pragma once

#include <optional>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "render/RenderTestSupport.h"

namespace sluice::rt::renderstage {

using namespace test;

inline constexpr glm::uvec2 kSize{320, 240};

using RenderTest = gpu::test::GpuTest;

// One scene, its simulation and renderer, and the camera of the file.
struct Stage {
    format::Scene scene;
    std::optional<Simulation> sim;
    std::optional<Renderer> renderer;
    OrbitCamera camera;

    explicit Stage(const std::string& json, bool deterministic = false)
        : Stage(sceneFromJson(json), deterministic) {}
    explicit Stage(format::Scene s, bool deterministic = false) : scene(std::move(s)) {
        auto colliders = collidersOf(scene);
        auto r = Renderer::create(scene, colliders, kSize);
        EXPECT_TRUE(r) << r.error().message();
        SimulationOptions options;
        options.deterministic = deterministic;
        auto created = Simulation::create(scene, std::move(colliders), options);
        EXPECT_TRUE(created) << created.error().message();
        if (!r || !created)
            return;
        renderer.emplace(std::move(*r));
        sim.emplace(std::move(*created));
        camera = sceneCamera(scene, renderer->bounds(), float(kSize.x) / float(kSize.y));
    }
    bool ok() const { return sim && renderer; }

    Image draw(const RenderSettings& settings = {}) {
        renderer->render(*sim, camera, settings);
        return renderer->readPixels();
    }
    // The same frame with every particle removed.
    Image drawWithoutParticles(const RenderSettings& settings = {}) {
        const auto particles = sim->downloadParticles();
        EXPECT_TRUE(sim->setParticles({}));
        Image image = draw(settings);
        EXPECT_TRUE(sim->setParticles(particles));
        return image;
    }
};

inline const char* kBlockScene = R"({
    "simulation": { "spacing": 0.02 },
    "fluid": [ { "box": { "min": [-0.1, 0.0, -0.1], "max": [0.1, 0.2, 0.1] } } ],
    "camera": { "position": [0.8, 0.6, 0.9], "target": [0.0, 0.1, 0.0], "fov": 45 }
})";

} // namespace sluice::rt::renderstage
