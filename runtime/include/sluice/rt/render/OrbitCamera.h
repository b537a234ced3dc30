// The viewer's camera: orbits a target point, pans in the view plane and zooms towards the
// target, and gives the view and projection matrices every render pass uses.
#pragma once

#include <glm/glm.hpp>

namespace sluice::rt {

/// An axis-aligned box in world units, for framing [m].
struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};

    glm::vec3 centre() const { return 0.5f * (min + max); }
    /// Radius of the sphere through the corners [m].
    float radius() const { return 0.5f * glm::length(max - min); }
};

/// A camera looking at `target()` from `distance()` metres away, in the direction given by a
/// yaw about +y and a pitch above the horizontal. +y is up; the camera never rolls.
class OrbitCamera {
public:
    /// Pitch is kept inside +-kMaxPitch [radians], so the view never flips over the pole.
    static constexpr float kMaxPitch = 1.55f;
    /// Distance limits [m].
    static constexpr float kMinDistance = 1e-3f;
    static constexpr float kMaxDistance = 1e4f;

    /// A camera at `eye` looking at `target` [m] with a vertical field of view [degrees].
    /// Precondition: eye != target; fovDegrees in (0, 180).
    static OrbitCamera lookAt(glm::vec3 eye, glm::vec3 target, float fovDegrees);

    /// Yaw and pitch change [radians] (drag to the right turns the camera left around the
    /// target, as in most viewers). Pitch is clamped.
    void orbit(float yawRadians, float pitchRadians);
    /// Moves the target (and the eye with it) in the view plane so that a point at the target's
    /// depth follows a cursor moved by `deltaPixels` (x right, y down) in a viewport
    /// `viewportHeight` pixels tall.
    void pan(glm::vec2 deltaPixels, float viewportHeight);
    /// Multiplies the distance to the target by `factor` (< 1 moves closer), clamped.
    void zoom(float factor);
    /// Keeps the direction; centres `bounds` and moves back until its bounding sphere fits the
    /// narrower field of view of a viewport with this aspect ratio (width / height).
    void frame(const Bounds& bounds, float aspect);

    glm::vec3 target() const { return m_target; }
    glm::vec3 eye() const;
    float distance() const { return m_distance; }
    float yaw() const { return m_yaw; }     ///< [radians]
    float pitch() const { return m_pitch; } ///< [radians]
    float fovDegrees() const { return m_fovDegrees; }
    /// Near and far plane distances [m], following the distance so depth keeps its precision.
    float nearPlane() const;
    float farPlane() const;

    /// World -> view.
    glm::mat4 view() const;
    /// View -> clip for a viewport of this aspect ratio (width / height); OpenGL depth [-1, 1].
    glm::mat4 projection(float aspect) const;
    /// Window position of a world point in a viewport of `size` pixels: x right from the left
    /// edge, y down from the top edge (image rows), z the window depth [0, 1]. Points behind
    /// the eye give z outside [0, 1].
    glm::vec3 project(glm::vec3 world, glm::uvec2 size) const;

private:
    glm::vec3 m_target{0.0f};
    float m_distance = 1.0f;
    float m_yaw = 0.0f;
    float m_pitch = 0.0f;
    float m_fovDegrees = 45.0f;
};

} // namespace sluice::rt
