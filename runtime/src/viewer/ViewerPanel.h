// The viewer's Dear ImGui panel (live parameters, modes, statistics, dynamic bodies, capture)
// and its help overlay with the key bindings.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "viewer/ViewerBodies.h"
#include "viewer/ViewerPick.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/rt/sim/Simulation.h"
#include "sluice/rt/render/FluidStatsProbe.h"
#include "sluice/rt/render/OrbitCamera.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {

/// What the user asked for this frame, from the panel or the keys.
struct ViewerActions {
    bool step = false;   ///< one step while paused
    bool reset = false;  ///< back to the scene's initial state
    bool reload = false; ///< read the scene file again
    bool frame = false;  ///< frame the scene with the camera
    bool screenshot = false;
    bool toggleRecording = false;
    bool quit = false;
    bool applyParameters = false; ///< ViewerUi::params was edited
    std::optional<bool> emitters; ///< turn the emitters on or off
};

/// What the panel shows and edits; the viewer keeps it across frames.
struct ViewerUi {
    bool paused = false;
    bool showPanel = true;
    bool showHelp = false;
    bool recording = false;
    bool screenshotPanel = false; ///< screenshots include the panel (and the help overlay)
    std::int32_t stepsPerFrame = 1;
    RenderSettings render;
    format::SimulationParams params; ///< the values being edited
    bool emitters = true;
    std::string status; ///< last message: a file written, an error
};

/// Figures for the statistics section, measured without waiting for the GPU.
struct ViewerFigures {
    std::string sceneName;
    std::uint32_t particles = 0;
    std::uint32_t capacity = 0;
    std::uint64_t steps = 0;
    double time = 0.0;           ///< simulated [s]
    double stepsPerSecond = 0.0; ///< over the last second of wall time
    double frameMs = 0.0;        ///< wall time per frame, averaged
    std::optional<double> renderGpuMs;
    RenderPassTimes renderPassMs{}; ///< GPU time per render pass, negative if unknown
    PassTimes passMs{};             ///< the simulation's GPU time per pass, negative if unknown
    std::optional<FluidStats> fluid;
    bool hasEmitters = false;
    std::vector<BodyRow> bodies;           ///< the dynamic bodies; empty: no Bodies section
    std::optional<std::uint32_t> heldBody; ///< the body the mouse spring holds
};

/// The panel's widest share of the window's width.
inline constexpr float kPanelMaxWidthFraction = 0.30f;

/// Where the panel goes in the window [pixels].
struct PanelLayout {
    glm::vec2 position{10.0f, 10.0f}; ///< top-left corner
    float width = 0.0f;               ///< fixed width
    float maxHeight = 0.0f;           ///< the panel fits its contents up to this height
    float itemWidth = 0.0f;           ///< width of a slider beside its label
};

/// The panel's layout in a window of `display` pixels, for labels up to `labelWidth` pixels wide
/// in a font `fontSize` pixels tall: the widest label, a slider 9 font sizes wide and 3 font
/// sizes of padding and scroll bar, capped at kPanelMaxWidthFraction of the window's width
/// (the sliders shrink first, so labels are never cut while the window is wider than about
/// three labels).
PanelLayout panelLayout(float labelWidth, float fontSize, glm::vec2 display);

/// Draws the panel (inside an ImGui frame) and records the user's requests in `actions`.
void drawViewerPanel(ViewerUi& ui, const ViewerFigures& figures, ViewerActions& actions);

/// Draws, behind the ImGui windows and over the scene, a ring where the mouse spring pulls and a
/// line to it from the grabbed point (at its body's pose in `bodies`, when it is there), seen by
/// `camera` in a window of `window` [screen coordinates].
void drawDragMarker(const BodyGrab& grab, const std::vector<BodyState>& bodies,
                    const OrbitCamera& camera, glm::uvec2 window);

/// Draws the key and mouse bindings in a window in the middle of the screen.
void drawViewerHelp(bool& open);

/// The key bindings as plain text lines ("Space  pause / resume"), for the overlay and --help.
const char* viewerKeyHelp();

} // namespace sluice::rt
