// Orbit camera math: spherical placement around the target, panning in the view plane, framing.
#include "sluice/rt/render/OrbitCamera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "sluice/format/support/Assert.h"

namespace sluice::rt {

OrbitCamera OrbitCamera::lookAt(glm::vec3 eye, glm::vec3 target, float fovDegrees) {
    SLUICE_ASSERT(fovDegrees > 0.0f && fovDegrees < 180.0f, "OrbitCamera: fov out of range");
    const glm::vec3 offset = eye - target;
    const float distance = glm::length(offset);
    SLUICE_ASSERT(distance > 0.0f, "OrbitCamera::lookAt: eye == target");
    OrbitCamera camera;
    camera.m_target = target;
    camera.m_distance = std::clamp(distance, kMinDistance, kMaxDistance);
    camera.m_yaw = std::atan2(offset.x, offset.z);
    camera.m_pitch =
        std::clamp(std::asin(std::clamp(offset.y / distance, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
    camera.m_fovDegrees = fovDegrees;
    return camera;
}

void OrbitCamera::orbit(float yawRadians, float pitchRadians) {
    m_yaw = std::remainder(m_yaw + yawRadians, 2.0f * glm::pi<float>());
    m_pitch = std::clamp(m_pitch + pitchRadians, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(glm::vec2 deltaPixels, float viewportHeight) {
    if (viewportHeight <= 0.0f)
        return;
    // Metres per pixel at the target's depth.
    const float perPixel =
        2.0f * m_distance * std::tan(glm::radians(m_fovDegrees) * 0.5f) / viewportHeight;
    const glm::mat4 v = view();
    const glm::vec3 right(v[0][0], v[1][0], v[2][0]);
    const glm::vec3 up(v[0][1], v[1][1], v[2][1]);
    // The scene follows the cursor: the camera moves the other way.
    m_target += perPixel * (-deltaPixels.x * right + deltaPixels.y * up);
}

void OrbitCamera::zoom(float factor) {
    if (!(factor > 0.0f))
        return;
    m_distance = std::clamp(m_distance * factor, kMinDistance, kMaxDistance);
}

void OrbitCamera::frame(const Bounds& bounds, float aspect) {
    const float radius = std::max(bounds.radius(), 1e-3f);
    const float halfFovY = glm::radians(m_fovDegrees) * 0.5f;
    const float halfFovX = std::atan(std::tan(halfFovY) * std::max(aspect, 1e-3f));
    const float halfFov = std::min(halfFovX, halfFovY);
    m_target = bounds.centre();
    // A sphere of this radius fits a cone of this half angle from this distance; a little margin.
    m_distance = std::clamp(1.05f * radius / std::sin(halfFov), kMinDistance, kMaxDistance);
}

glm::vec3 OrbitCamera::eye() const {
    const float c = std::cos(m_pitch);
    return m_target +
           m_distance * glm::vec3(c * std::sin(m_yaw), std::sin(m_pitch), c * std::cos(m_yaw));
}

float OrbitCamera::nearPlane() const {
    return std::max(1e-3f, 0.01f * m_distance);
}

float OrbitCamera::farPlane() const {
    return 100.0f * m_distance + 10.0f;
}

glm::mat4 OrbitCamera::view() const {
    return glm::lookAt(eye(), m_target, glm::vec3(0.0f, 1.0f, 0.0f));
}

glm::mat4 OrbitCamera::projection(float aspect) const {
    return glm::perspective(glm::radians(m_fovDegrees), aspect, nearPlane(), farPlane());
}

glm::vec3 OrbitCamera::project(glm::vec3 world, glm::uvec2 size) const {
    const float aspect = float(size.x) / float(std::max(size.y, 1u));
    const glm::vec4 clip = projection(aspect) * view() * glm::vec4(world, 1.0f);
    const glm::vec3 ndc = glm::vec3(clip) / clip.w;
    const float x = (0.5f * ndc.x + 0.5f) * float(size.x);
    const float y = (0.5f - 0.5f * ndc.y) * float(size.y);
    const float z = clip.w > 0.0f ? 0.5f * ndc.z + 0.5f : -1.0f;
    return {x, y, z};
}

} // namespace sluice::rt
