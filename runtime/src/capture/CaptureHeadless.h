// A headless run's pictures: renders the steps that --frames, --video and --screenshot-at ask
// for into an offscreen framebuffer (EGL, no window), reads them back without stalling and
// writes them.
#pragma once

#include <cstdint>
#include <deque>
#include <iosfwd>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "capture/CaptureFrames.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/rt/render/FrameReadback.h"
#include "sluice/rt/render/OrbitCamera.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {

class Simulation;

/// Renderer, camera, readback ring and frame writer of one headless run. Move-only; needs the
/// simulation's context current.
class HeadlessCapture {
public:
    /// Checks the options (starts ffmpeg for a video, creates the frames folder) and creates a
    /// renderer of `size` for the scene, seen by the scene's camera.
    static Result<HeadlessCapture> start(const format::Scene& scene,
                                         const std::vector<format::ColliderAsset>& colliders,
                                         const CaptureOptions& options, glm::uvec2 size,
                                         const RenderSettings& settings);

    /// Renders and queues the current state if step `step` is to be captured, and writes the
    /// frames whose readback has finished.
    Result<void> afterStep(const Simulation& sim, std::uint64_t step);

    /// Writes every frame still in flight and finishes the video. Call once, at the end.
    Result<void> finish();

    /// Says what was rendered, written and where ("rendered 61 frames of 640x360", ...).
    void report(std::ostream& out) const;

private:
    struct Pending {
        bool frame = false;      // --frames / --video
        bool screenshot = false; // --screenshot-at
    };

    HeadlessCapture(Renderer renderer, OrbitCamera camera);
    Result<void> writeReady(bool wait);

    Renderer m_renderer;
    OrbitCamera m_camera;
    RenderSettings m_settings;
    CaptureOptions m_options;
    std::string m_sceneName;
    std::optional<FrameCapture> m_frames;
    FrameReadback m_readback{3};
    std::deque<Pending> m_pending;
    std::vector<std::string> m_screenshots;
    std::uint64_t m_rendered = 0;
};

} // namespace sluice::rt
