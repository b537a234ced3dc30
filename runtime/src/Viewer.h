// sluice-play's window: GLFW with an OpenGL 4.5 core context, the scene rendered every frame,
// mouse camera, keys, the ImGui panel, screenshots, recording and --frames/--video capture.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "CaptureFrames.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {

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
};

/// Opens the window and runs until it is closed (or maxFrames); returns the exit code:
/// 0, 2 for a bad scene or capture setting, 3 when there is no display or no GL 4.5 core
/// context, with a message on stderr that says what to do.
int runViewer(const ViewerOptions& options);

} // namespace sluice::rt
