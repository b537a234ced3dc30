// Shared by the render and viewer tests: scenes written inline against the build's baked
// colliders, one-call renders, PNG reading and image comparison.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <stb_image.h>

#include "ProgramRun.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/sim/Simulation.h"
#include "sluice/rt/render/Image.h"
#include "sluice/rt/render/Renderer.h"
#include "sluice/rt/render/SceneFraming.h"

namespace sluice::rt::test {

namespace fs = std::filesystem;

/// Scenes and baked colliders of the build, side by side.
inline const fs::path kAssets = SLUICE_BUILD_ASSETS_DIR;

/// An empty folder for one test's files.
using testrun::tempDir;

/// A scene from JSON text whose collider assets are named relative to the build's assets.
inline format::Scene sceneFromJson(const std::string& json) {
    auto scene = format::parseScene(json, kAssets / "render-test.json");
    EXPECT_TRUE(scene) << scene.error().message();
    return scene ? std::move(*scene) : format::Scene{};
}

/// The build's wave-sphere.json (its colliders carry the volume maps it needs, baked by the
/// build, so a load takes a fraction of a second on llvmpipe).
inline format::Scene waveSphere() {
    auto scene = format::readScene(kAssets / "wave-sphere.json");
    EXPECT_TRUE(scene) << scene.error().message();
    return scene ? std::move(*scene) : format::Scene{};
}

/// The scene's colliders, read from the build's assets.
inline std::vector<format::ColliderAsset> collidersOf(const format::Scene& scene) {
    auto colliders = loadSceneColliders(scene);
    EXPECT_TRUE(colliders) << colliders.error().message();
    return colliders ? std::move(*colliders) : std::vector<format::ColliderAsset>{};
}

/// The image of `scene` after `steps` steps, seen by its own camera.
inline Image renderScene(const format::Scene& scene, glm::uvec2 size,
                         const RenderSettings& settings = {}, int steps = 0,
                         bool deterministic = false) {
    auto colliders = collidersOf(scene);
    auto renderer = Renderer::create(scene, colliders, size);
    EXPECT_TRUE(renderer) << renderer.error().message();
    SimulationOptions options;
    options.deterministic = deterministic;
    auto sim = Simulation::create(scene, std::move(colliders), options);
    EXPECT_TRUE(sim) << sim.error().message();
    if (!renderer || !sim)
        return {};
    for (int i = 0; i < steps; ++i)
        sim->step();
    const OrbitCamera camera =
        sceneCamera(scene, renderer->bounds(), float(size.x) / float(size.y));
    renderer->render(*sim, camera, settings);
    return renderer->readPixels();
}

/// Runs sluice-play with `args` in `dir` (see testrun::runProgram).
inline testrun::RunResult runPlay(const fs::path& dir, const std::vector<std::string>& args) {
    return testrun::runProgram(SLUICE_PLAY_EXE, dir, args);
}

/// A PNG file as an RGB image (empty if it cannot be read).
inline Image readPng(const fs::path& path) {
    int w = 0, h = 0, channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
    if (data == nullptr)
        return {};
    Image image = Image::blank(std::uint32_t(w), std::uint32_t(h));
    std::copy(data, data + image.rgb.size(), image.rgb.begin());
    stbi_image_free(data);
    return image;
}

/// How two images of one size differ.
struct ImageDiff {
    int maxChannel = 0;       ///< largest |a - b| of one channel [0, 255]
    double meanChannel = 0.0; ///< mean |a - b| over every channel
    std::size_t pixels = 0;   ///< pixels with any channel different
};

inline ImageDiff compareImages(const Image& a, const Image& b) {
    ImageDiff diff;
    if (a.width != b.width || a.height != b.height) {
        ADD_FAILURE() << "images differ in size: " << a.width << "x" << a.height << " and "
                      << b.width << "x" << b.height;
        diff.maxChannel = 255;
        return diff;
    }
    double sum = 0.0;
    for (std::size_t p = 0; p < a.rgb.size(); p += 3) {
        bool differs = false;
        for (std::size_t c = 0; c < 3; ++c) {
            const int d = std::abs(int(a.rgb[p + c]) - int(b.rgb[p + c]));
            diff.maxChannel = std::max(diff.maxChannel, d);
            sum += d;
            differs = differs || d != 0;
        }
        diff.pixels += differs ? 1 : 0;
    }
    diff.meanChannel = a.rgb.empty() ? 0.0 : sum / double(a.rgb.size());
    return diff;
}

/// Whether pixel (x, y) differs between two images of one size (any channel by more than 2).
inline bool pixelDiffers(const Image& a, const Image& b, std::uint32_t x, std::uint32_t y) {
    const glm::ivec3 d = glm::abs(glm::ivec3(a.at(x, y)) - glm::ivec3(b.at(x, y)));
    return std::max({d.x, d.y, d.z}) > 2;
}

} // namespace sluice::rt::test
