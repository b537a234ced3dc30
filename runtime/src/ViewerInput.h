// The viewer's keyboard and mouse: GLFW events to camera moves, panel toggles and actions
// (the bindings are listed by viewerKeyHelp() in ViewerPanel.h).
#pragma once

#include <glm/glm.hpp>

#include "ViewerPanel.h"
#include "sluice/rt/render/OrbitCamera.h"

struct GLFWwindow;

namespace sluice::rt {

/// Mouse drag state across events. The window filters out events ImGui wants first.
class ViewerInput {
public:
    /// A key press or repeat (GLFW codes): toggles in `ui`, requests in `actions`.
    void key(int key, int action, int mods, ViewerUi& ui, ViewerActions& actions);
    /// A button press starts a drag (left: orbit, Shift + left, right or middle: pan); a
    /// release ends it.
    void mouseButton(GLFWwindow* window, int button, int action, int mods);
    /// The cursor moved to (x, y) [screen coordinates] in a window `height` tall: orbits or
    /// pans `camera` while dragging.
    void cursor(double x, double y, int height, OrbitCamera& camera);
    /// The camera distance factor for a wheel movement of `dy` notches (0.9 per notch).
    static float zoomFactor(double dy);

private:
    enum class Drag { None, Orbit, Pan };
    Drag m_drag = Drag::None;
    glm::dvec2 m_cursor{0.0};
};

} // namespace sluice::rt
