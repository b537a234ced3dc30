// Picking in the viewer window: the ray under the cursor, and the state of a body held by the
// mouse spring (Ctrl + left drag).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "sluice/rt/render/OrbitCamera.h"

namespace sluice::rt {

/// A half-line in world space.
struct Ray {
    glm::vec3 origin{0.0f};                 ///< [m]
    glm::vec3 direction{0.0f, 0.0f, -1.0f}; ///< unit length

    /// The point `distance` [m] along the ray.
    glm::vec3 at(float distance) const { return origin + distance * direction; }
};

/// The ray from the camera's eye through the window point `cursor` [screen coordinates: x right
/// from the left edge, y down from the top edge] of a window `window` [screen coordinates] wide
/// and tall; the inverse of OrbitCamera::project for the same size: the window's centre looks
/// at the orbit target. Precondition: window.x, window.y > 0.
Ray cursorRay(const OrbitCamera& camera, glm::dvec2 cursor, glm::dvec2 window);

/// A dynamic body held by the mouse spring: the grabbed point stays on the cursor's ray at the
/// distance where the ray first met the body.
struct BodyGrab {
    std::uint32_t body = 0; ///< index into Simulation::bodies()
    glm::vec3 anchor{0.0f}; ///< the grabbed point in the body's asset frame [asset units]
    float distance = 0.0f;  ///< from the ray's origin (the eye) to the grabbed point [m]
    glm::vec3 target{0.0f}; ///< where the spring pulls the anchor now [m]
};

} // namespace sluice::rt
