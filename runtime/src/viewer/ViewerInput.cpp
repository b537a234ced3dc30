// Key bindings and mouse drags of the viewer window.
#include "viewer/ViewerInput.h"

#include <cmath>

#include "sluice/gpu/Gl.h" // glad first: GLFW must not include the system GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace sluice::rt {

void ViewerInput::key(int key, int action, int mods, ViewerUi& ui, ViewerActions& actions) {
    (void)mods;
    if (action != GLFW_PRESS && action != GLFW_REPEAT)
        return;
    // Toggles act on the press only; stepping repeats while the key is held.
    const bool press = action == GLFW_PRESS;
    switch (key) {
    case GLFW_KEY_N:
    case GLFW_KEY_RIGHT:
        actions.step = true;
        return;
    default:
        break;
    }
    if (!press)
        return;
    switch (key) {
    case GLFW_KEY_SPACE:
        ui.paused = !ui.paused;
        break;
    case GLFW_KEY_R:
        actions.reset = true;
        break;
    case GLFW_KEY_F:
        actions.frame = true;
        break;
    case GLFW_KEY_P:
    case GLFW_KEY_F12:
        actions.screenshot = true;
        break;
    case GLFW_KEY_V:
        actions.toggleRecording = true;
        break;
    case GLFW_KEY_TAB:
        ui.showPanel = !ui.showPanel;
        break;
    case GLFW_KEY_F1:
    case GLFW_KEY_H:
        ui.showHelp = !ui.showHelp;
        break;
    case GLFW_KEY_C:
        ui.render.colour = ColourMode((std::uint32_t(ui.render.colour) + 1) % 3);
        break;
    case GLFW_KEY_M:
        // Spheres, the screen-space fluid, the reconstructed mesh (what --surface-mesh writes).
        ui.render.surface = SurfaceMode((std::uint32_t(ui.render.surface) + 1) % 3);
        break;
    case GLFW_KEY_G:
        ui.render.glassWalls = !ui.render.glassWalls;
        break;
    case GLFW_KEY_O:
        ui.screenshotPanel = !ui.screenshotPanel;
        ui.status =
            ui.screenshotPanel ? "screenshots include the panel" : "screenshots without the panel";
        break;
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
        actions.quit = true;
        break;
    default:
        break;
    }
}

void ViewerInput::mouseButton(int button, int action, int mods, glm::dvec2 cursor) {
    m_cursor = cursor;
    if (action == GLFW_RELEASE) {
        m_drag = Drag::None;
        m_grabRequest = false;
        return;
    }
    if (action != GLFW_PRESS)
        return;
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
        // Ctrl, not Shift: Shift + left already pans, for one-button mice.
        if ((mods & GLFW_MOD_CONTROL) != 0) {
            m_drag = Drag::Body;
            m_grabRequest = true;
        } else {
            m_drag = (mods & GLFW_MOD_SHIFT) != 0 ? Drag::Pan : Drag::Orbit;
        }
    } else if (button == GLFW_MOUSE_BUTTON_RIGHT || button == GLFW_MOUSE_BUTTON_MIDDLE) {
        m_drag = Drag::Pan;
    }
}

void ViewerInput::cursor(double x, double y, int height, OrbitCamera& camera) {
    const glm::dvec2 now(x, y);
    const glm::vec2 delta(now - m_cursor);
    m_cursor = now;
    if (height <= 0)
        return;
    if (m_drag == Drag::Orbit) {
        // A drag across the window's height turns the camera by about 180 degrees.
        const float perPixel = 3.14159265f / float(height);
        camera.orbit(-delta.x * perPixel, delta.y * perPixel);
    } else if (m_drag == Drag::Pan) {
        camera.pan(delta, float(height));
    }
}

float ViewerInput::zoomFactor(double dy) {
    return float(std::pow(0.9, dy));
}

bool ViewerInput::takeGrabRequest() {
    const bool request = m_grabRequest;
    m_grabRequest = false;
    return request;
}

} // namespace sluice::rt
