// Cursor rays through the orbit camera, for picking bodies with the mouse.
#include "viewer/ViewerPick.h"

#include <cmath>

#include "sluice/format/support/Assert.h"

namespace sluice::rt {

Ray cursorRay(const OrbitCamera& camera, glm::dvec2 cursor, glm::dvec2 window) {
    SLUICE_ASSERT(window.x > 0.0 && window.y > 0.0, "cursorRay: empty window");
    // Normalised device coordinates of the cursor, y up (OrbitCamera::project backwards).
    const glm::dvec2 ndc(2.0 * cursor.x / window.x - 1.0, 1.0 - 2.0 * cursor.y / window.y);
    // The view frustum's slopes, as in glm::perspective(fovy, aspect).
    const double tanHalfY = std::tan(glm::radians(double(camera.fovDegrees())) * 0.5);
    const double tanHalfX = tanHalfY * window.x / window.y;
    // The camera's axes in world space are the rows of the view rotation.
    const glm::mat4 v = camera.view();
    const glm::dvec3 right(v[0][0], v[1][0], v[2][0]);
    const glm::dvec3 up(v[0][1], v[1][1], v[2][1]);
    const glm::dvec3 forward(-v[0][2], -v[1][2], -v[2][2]);
    const glm::dvec3 direction =
        glm::normalize(forward + ndc.x * tanHalfX * right + ndc.y * tanHalfY * up);
    return Ray{camera.eye(), glm::vec3(direction)};
}

} // namespace sluice::rt
