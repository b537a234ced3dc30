// The orbit camera's math: placement, orbit, pan, zoom, framing and projection (CPU only).
#include <cmath>

#include <gtest/gtest.h>

#include "VecExpect.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/rt/render/OrbitCamera.h"
#include "sluice/rt/render/SceneFraming.h"

namespace sluice::rt {
namespace {

constexpr float kTol = 1e-4f;

void expectNear(glm::vec3 a, glm::vec3 b, float tol = kTol) {
    test::expectVecNear(a, b, tol);
}

TEST(OrbitCamera, LookAtPutsTheEyeWhereItWasAsked) {
    const auto camera = OrbitCamera::lookAt({1.1f, 0.9f, 1.3f}, {0.05f, 0.15f, 0.0f}, 45.0f);
    expectNear(camera.eye(), {1.1f, 0.9f, 1.3f});
    expectNear(camera.target(), {0.05f, 0.15f, 0.0f});
    EXPECT_NEAR(camera.distance(), glm::length(glm::vec3(1.05f, 0.75f, 1.3f)), kTol);
}

TEST(OrbitCamera, ProjectsTheTargetToTheViewportCentre) {
    const auto camera = OrbitCamera::lookAt({2.0f, 1.0f, -1.0f}, {0.3f, 0.2f, 0.1f}, 40.0f);
    const glm::vec3 p = camera.project({0.3f, 0.2f, 0.1f}, {320, 240});
    EXPECT_NEAR(p.x, 160.0f, 1e-3f);
    EXPECT_NEAR(p.y, 120.0f, 1e-3f);
    EXPECT_GT(p.z, 0.0f);
    EXPECT_LT(p.z, 1.0f);
    // Up in the world is up on the screen (smaller row), and behind the eye is off the range.
    EXPECT_LT(camera.project({0.3f, 0.3f, 0.1f}, {320, 240}).y, 120.0f);
    EXPECT_LT(camera.project(camera.eye() + (camera.eye() - camera.target()), {320, 240}).z, 0.0f);
}

TEST(OrbitCamera, OrbitKeepsTheDistanceAndTheTarget) {
    auto camera = OrbitCamera::lookAt({0.0f, 0.0f, 2.0f}, glm::vec3(0.0f), 45.0f);
    camera.orbit(glm::radians(90.0f), 0.0f);
    expectNear(camera.eye(), {2.0f, 0.0f, 0.0f});
    camera.orbit(0.0f, glm::radians(30.0f));
    EXPECT_NEAR(glm::length(camera.eye() - camera.target()), 2.0f, kTol);
    EXPECT_NEAR(camera.eye().y, 2.0f * std::sin(glm::radians(30.0f)), kTol);
    // The pitch stops short of the pole, so the view never flips.
    camera.orbit(0.0f, 10.0f);
    EXPECT_FLOAT_EQ(camera.pitch(), OrbitCamera::kMaxPitch);
}

TEST(OrbitCamera, PanMovesTheTargetPointUnderTheCursor) {
    auto camera = OrbitCamera::lookAt({0.0f, 0.0f, 2.0f}, glm::vec3(0.0f), 90.0f);
    // At distance 2 with a 90 degree field, 200 pixels of height span 4 m: 0.02 m per pixel.
    camera.pan({10.0f, 0.0f}, 200.0f);
    expectNear(camera.target(), {-0.2f, 0.0f, 0.0f});
    camera.pan({0.0f, 10.0f}, 200.0f);
    expectNear(camera.target(), {-0.2f, 0.2f, 0.0f});
    EXPECT_NEAR(camera.distance(), 2.0f, kTol);
}

TEST(OrbitCamera, ZoomScalesTheDistanceWithinItsLimits) {
    auto camera = OrbitCamera::lookAt({0.0f, 0.0f, 2.0f}, glm::vec3(0.0f), 45.0f);
    camera.zoom(0.5f);
    EXPECT_NEAR(camera.distance(), 1.0f, kTol);
    camera.zoom(1e-9f);
    EXPECT_FLOAT_EQ(camera.distance(), OrbitCamera::kMinDistance);
    camera.zoom(-1.0f); // ignored
    EXPECT_FLOAT_EQ(camera.distance(), OrbitCamera::kMinDistance);
}

TEST(OrbitCamera, FramingKeepsEveryCornerOfTheBoxOnScreen) {
    const Bounds box{{-0.5f, 0.0f, -0.35f}, {0.5f, 0.7f, 0.35f}};
    for (const glm::uvec2 size : {glm::uvec2(320, 240), glm::uvec2(200, 400)}) {
        auto camera = OrbitCamera::lookAt({5.0f, 3.0f, 4.0f}, {9.0f, 9.0f, 9.0f}, 45.0f);
        camera.frame(box, float(size.x) / float(size.y));
        expectNear(camera.target(), box.centre());
        float nearest = 1e9f;
        for (int c = 0; c < 8; ++c) {
            const glm::vec3 corner((c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                                   (c & 4) ? box.max.z : box.min.z);
            const glm::vec3 p = camera.project(corner, size);
            EXPECT_GE(p.x, 0.0f);
            EXPECT_LE(p.x, float(size.x));
            EXPECT_GE(p.y, 0.0f);
            EXPECT_LE(p.y, float(size.y));
            nearest = std::min({nearest, p.x, float(size.x) - p.x, p.y, float(size.y) - p.y});
        }
        // ...and fills a good part of it: not framed from absurdly far away.
        EXPECT_LT(nearest, 0.3f * float(std::min(size.x, size.y))) << size.x << "x" << size.y;
    }
}

TEST(SceneFraming, BoundsHoldTheDomainBlocksAndEmitters) {
    auto scene = format::parseScene(R"({
        "fluid": [ { "box": { "min": [0, 0, 0], "max": [0.2, 0.2, 0.2] } } ],
        "emitters": [ { "position": [0, 1.5, 0], "direction": [0, -1, 0], "radius": 0.05,
                        "speed": 1 } ],
        "domain": { "min": [-1, -0.5, -1], "max": [1, 1, 1] }
    })",
                                    "bounds.json");
    ASSERT_TRUE(scene) << scene.error().message();
    const Bounds b = sceneBounds(*scene, {});
    expectNear(b.min, {-1.0f, -0.5f, -1.0f});
    expectNear(b.max, {1.0f, 1.55f, 1.0f});
    EXPECT_FLOAT_EQ(floorHeight(*scene, b), -0.5f);
    // Without a camera in the file, the scene is framed from above the front right.
    const OrbitCamera camera = sceneCamera(*scene, b, 4.0f / 3.0f);
    expectNear(camera.target(), b.centre());
    EXPECT_GT(camera.eye().y, camera.target().y);
}

} // namespace
} // namespace sluice::rt
