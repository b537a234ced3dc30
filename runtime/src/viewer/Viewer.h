// sluice-play's window: GLFW with an OpenGL 4.5 core context, the scene rendered every frame,
// mouse camera, keys, the ImGui panel, bodies pulled with the mouse, screenshots, recording and
// --frames/--video capture.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "capture/CaptureFrames.h"
#include "viewer/ViewerPanel.h"
#include "viewer/ViewerSession.h"
#include "sluice/rt/render/OrbitCamera.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {

/// A running viewer as a test script sees it (ViewerOptions::script): mouse input fed through
/// the same path as GLFW's callbacks, and the state they act on.
class ViewerControl {
public:
    virtual ~ViewerControl() = default;
    /// Frames drawn so far.
    virtual std::uint64_t frames() const = 0;
    /// A mouse button event (GLFW codes) with the cursor at `cursor` [screen coordinates].
    virtual void mouseButton(int button, int action, int mods, glm::dvec2 cursor) = 0;
    /// The cursor moved to `cursor` [screen coordinates].
    virtual void moveCursor(glm::dvec2 cursor) = 0;
    /// The window's size [screen coordinates], the frame the cursor is given in.
    virtual glm::uvec2 windowSize() const = 0;
    virtual const OrbitCamera& camera() const = 0;
    virtual ViewerSession& session() = 0;
    virtual ViewerUi& ui() = 0;
};

/// The window flags of sluice-play.
struct ViewerOptions {
    std::string scene;
    glm::uvec2 size{1280, 720}; ///< initial window size [pixels]
    bool vsync = true;
    bool panel = true; ///< start with the panel shown
    bool screenshotPanel = false; ///< screenshots include the panel (the O key toggles it)
    bool deterministic = false;
    bool quiet = false;
    std::uint64_t maxFrames = 0; ///< close after this many frames; 0: when the user does
    std::uint32_t stepsPerFrame = 1;
    RenderSettings settings;
    CaptureOptions capture; ///< --frames, --video, --screenshot-at, --shots
    /// For tests: called at the start of every frame, after the window's events and before the
    /// frame uses them. Empty in sluice-play.
    std::function<void(ViewerControl&)> script;
};

/// Opens the window and runs until it is closed (or maxFrames); returns the exit code:
/// 0, 2 for a bad scene or capture setting, 3 when there is no display or no GL 4.5 core
/// context, with a message on stderr that says what to do.
int runViewer(const ViewerOptions& options);

} // namespace sluice::rt
