// The viewer's keyboard and mouse: GLFW events to camera moves, panel toggles, actions and the
// body drag (the bindings are listed by viewerKeyHelp() in ViewerPanel.h).
#pragma once

#include <glm/glm.hpp>

#include "viewer/ViewerPanel.h"
#include "sluice/rt/render/OrbitCamera.h"

namespace sluice::rt {

/// Mouse drag state across events. The window filters out events ImGui wants first.
class ViewerInput {
public:
    /// A key press or repeat (GLFW codes): toggles in `ui`, requests in `actions`.
    void key(int key, int action, int mods, ViewerUi& ui, ViewerActions& actions);
    /// A button press (GLFW codes) with the cursor at `cursor` [screen coordinates] starts a
    /// drag: left orbits, Ctrl + left pulls a body (the window picks it: takeGrabRequest),
    /// Shift + left, right or middle pans. A release ends it.
    void mouseButton(int button, int action, int mods, glm::dvec2 cursor);
    /// The cursor moved to (x, y) [screen coordinates] in a window `height` tall: orbits or
    /// pans `camera` while dragging (a body drag leaves the camera alone).
    void cursor(double x, double y, int height, OrbitCamera& camera);
    /// The camera distance factor for a wheel movement of `dy` notches (0.9 per notch).
    static float zoomFactor(double dy);

    /// True once after each press that starts a body drag: the window should pick a body
    /// under cursorPosition() now.
    bool takeGrabRequest();
    /// A body drag's button is held.
    bool draggingBody() const { return m_drag == Drag::Body; }
    /// The cursor's latest position [screen coordinates].
    glm::dvec2 cursorPosition() const { return m_cursor; }

private:
    enum class Drag { None, Orbit, Pan, Body };
    Drag m_drag = Drag::None;
    bool m_grabRequest = false;
    glm::dvec2 m_cursor{0.0};
};

} // namespace sluice::rt
