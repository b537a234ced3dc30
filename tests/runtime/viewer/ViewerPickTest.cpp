// Picking without a window: the cursor's ray against the camera's own projection, and the mouse
// bindings that start a body drag, orbit or pan.
#include <cmath>

#include <gtest/gtest.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "viewer/ViewerInput.h"
#include "viewer/ViewerPick.h"

namespace sluice::rt {
namespace {

// Distance from `point` to the line of `ray` [m].
float distanceToRay(const Ray& ray, glm::vec3 point) {
    const glm::vec3 d = point - ray.origin;
    return glm::length(d - glm::dot(d, ray.direction) * ray.direction);
}

// Cameras of every kind the viewer makes: a scene's, orbited, panned, zoomed, wide and narrow.
std::vector<OrbitCamera> cameras() {
    std::vector<OrbitCamera> out;
    out.push_back(OrbitCamera::lookAt({1.1f, 0.9f, 1.3f}, {0.05f, 0.15f, 0.0f}, 45.0f));
    OrbitCamera turned = out.back();
    turned.orbit(2.0f, -0.7f);
    out.push_back(turned);
    OrbitCamera panned = OrbitCamera::lookAt({0.0f, 3.0f, 0.01f}, {0.0f, 0.0f, 0.0f}, 90.0f);
    panned.pan({40.0f, -25.0f}, 480.0f);
    panned.zoom(0.2f);
    out.push_back(panned);
    out.push_back(OrbitCamera::lookAt({-20.0f, 5.0f, 7.0f}, {1.0f, 2.0f, 3.0f}, 10.0f));
    return out;
}

const glm::dvec2 kWindows[] = {{1280.0, 720.0}, {320.0, 240.0}, {300.0, 900.0}};

TEST(ViewerPick, TheRayThroughTheWindowsCentreMeetsTheOrbitTarget) {
    for (const OrbitCamera& camera : cameras())
        for (const glm::dvec2 window : kWindows) {
            const Ray ray = cursorRay(camera, 0.5 * window, window);
            EXPECT_LT(glm::distance(ray.origin, camera.eye()), 1e-6f * camera.distance());
            EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-6f);
            EXPECT_LT(distanceToRay(ray, camera.target()), 1e-5f * camera.distance())
                << window.x << "x" << window.y;
            EXPECT_GT(glm::dot(camera.target() - ray.origin, ray.direction), 0.0f);
        }
}

TEST(ViewerPick, TheRayThroughAProjectedPointPassesThroughIt) {
    // Points spread over the view, in front of the eye: the ray through the pixel
    // OrbitCamera::project puts each at passes through it, so picking sees what is drawn.
    for (const OrbitCamera& camera : cameras())
        for (const glm::dvec2 window : kWindows) {
            const glm::mat4 view = camera.view();
            const glm::vec3 right(view[0][0], view[1][0], view[2][0]);
            const glm::vec3 up(view[0][1], view[1][1], view[2][1]);
            int seen = 0;
            for (int i = -3; i <= 3; ++i)
                for (int j = -3; j <= 3; ++j) {
                    // A quarter of the half-height of the view at the target's depth.
                    const float spread = 0.25f * camera.distance() *
                                         std::tan(glm::radians(camera.fovDegrees()) * 0.5f);
                    const glm::vec3 point = camera.target() + float(i) * spread * right +
                                            float(j) * spread * up +
                                            0.1f * float(i * j) * spread * glm::cross(right, up);
                    const glm::vec3 pixel = camera.project(point, glm::uvec2(window));
                    if (pixel.z <= 0.0f || pixel.z >= 1.0f || pixel.x < 0.0f || pixel.y < 0.0f ||
                        pixel.x > window.x || pixel.y > window.y)
                        continue;
                    ++seen;
                    const Ray ray = cursorRay(camera, glm::dvec2(pixel.x, pixel.y), window);
                    const float depth = glm::distance(ray.origin, point);
                    EXPECT_LT(distanceToRay(ray, point), 2e-5f * depth)
                        << "point " << i << ", " << j << " in " << window.x << "x" << window.y;
                    EXPECT_LT(glm::distance(ray.at(depth), point), 2e-5f * depth);
                }
            EXPECT_GT(seen, 12) << "too few test points in view";
        }
}

TEST(ViewerPick, TheWindowsEdgesLieOnTheFieldOfView) {
    const OrbitCamera camera = OrbitCamera::lookAt({0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 60.0f);
    const glm::dvec2 window(800.0, 400.0);
    const glm::vec3 forward = glm::normalize(camera.target() - camera.eye());
    // Top edge: half the vertical field of view above the view direction.
    const Ray top = cursorRay(camera, {400.0, 0.0}, window);
    EXPECT_NEAR(std::acos(glm::dot(top.direction, forward)), glm::radians(30.0f), 1e-5f);
    EXPECT_GT(top.direction.y, 0.0f);
    // Right edge: the horizontal half angle of a 2:1 window.
    const Ray right = cursorRay(camera, {800.0, 200.0}, window);
    EXPECT_NEAR(std::acos(glm::dot(right.direction, forward)),
                std::atan(2.0f * std::tan(glm::radians(30.0f))), 1e-5f);
    EXPECT_GT(right.direction.x, 0.0f);
}

TEST(ViewerInput, ControlLeftDragAsksForABodyAndLeavesTheCameraAlone) {
    ViewerInput input;
    OrbitCamera camera = OrbitCamera::lookAt({1.0f, 1.0f, 1.0f}, {0.0f, 0.0f, 0.0f}, 45.0f);
    const OrbitCamera before = camera;
    input.mouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, GLFW_MOD_CONTROL, {100.0, 120.0});
    EXPECT_TRUE(input.draggingBody());
    EXPECT_EQ(input.cursorPosition(), glm::dvec2(100.0, 120.0));
    EXPECT_TRUE(input.takeGrabRequest());
    EXPECT_FALSE(input.takeGrabRequest()); // once per press
    input.cursor(180.0, 40.0, 480, camera);
    EXPECT_EQ(input.cursorPosition(), glm::dvec2(180.0, 40.0));
    EXPECT_EQ(camera.eye(), before.eye());
    EXPECT_EQ(camera.target(), before.target());
    input.mouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, GLFW_MOD_CONTROL, {180.0, 40.0});
    EXPECT_FALSE(input.draggingBody());
}

TEST(ViewerInput, AClickReleasedBeforeTheFrameAsksForNoBody) {
    ViewerInput input;
    input.mouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, GLFW_MOD_CONTROL, {10.0, 10.0});
    input.mouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, GLFW_MOD_CONTROL, {10.0, 10.0});
    EXPECT_FALSE(input.takeGrabRequest());
    EXPECT_FALSE(input.draggingBody());
}

TEST(ViewerInput, LeftDragStillOrbitsAndShiftLeftOrRightDragStillPans) {
    ViewerInput input;
    OrbitCamera camera = OrbitCamera::lookAt({1.0f, 1.0f, 1.0f}, {0.0f, 0.0f, 0.0f}, 45.0f);
    input.mouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0, {100.0, 100.0});
    input.cursor(150.0, 100.0, 480, camera);
    EXPECT_FALSE(input.draggingBody());
    EXPECT_FALSE(input.takeGrabRequest());
    EXPECT_NE(camera.yaw(), OrbitCamera::lookAt({1.0f, 1.0f, 1.0f}, {}, 45.0f).yaw());
    EXPECT_EQ(camera.target(), glm::vec3(0.0f));
    input.mouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0, {150.0, 100.0});
    for (const auto& [button, mods] : {std::pair{GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_SHIFT},
                                       std::pair{GLFW_MOUSE_BUTTON_RIGHT, 0}}) {
        const float yaw = camera.yaw();
        const glm::vec3 target = camera.target();
        input.mouseButton(button, GLFW_PRESS, mods, {150.0, 100.0});
        input.cursor(170.0, 110.0, 480, camera);
        input.mouseButton(button, GLFW_RELEASE, mods, {170.0, 110.0});
        EXPECT_EQ(camera.yaw(), yaw) << button;
        EXPECT_NE(camera.target(), target) << button;
        EXPECT_FALSE(input.takeGrabRequest());
    }
}

} // namespace
} // namespace sluice::rt
