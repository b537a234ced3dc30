// What the viewer writes: --frames and --video of the steps it shows, screenshots (P,
// --screenshot-at, with or without the panel) and the V key's recording, each frame read back
// through fences a few frames later (FrameReadback), so no frame waits for the GPU.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include <glm/vec2.hpp>

#include "capture/CaptureFrames.h"
#include "capture/CaptureVideo.h"
#include "sluice/format/support/Result.h"
#include "sluice/rt/render/FrameReadback.h"
#include "viewer/Viewer.h"
#include "viewer/ViewerPanel.h"
#include "viewer/ViewerSession.h"

namespace sluice::rt {

/// The panel's status line says `done`, or the error, which also goes to stderr.
void reportStatus(ViewerUi& ui, const Result<void>& result, const std::string& done);

class ViewerOutputs {
public:
    explicit ViewerOutputs(const ViewerOptions& options) : m_options(options) {}

    /// Starts --frames / --video and creates the screenshots' folder.
    Result<void> start(ViewerSession& session);
    /// The V key: starts a recording at the window's size, or finishes the one running.
    void toggleRecording(ViewerSession& session, ViewerUi& ui);
    /// Queues the readbacks the frame just rendered needs: a capture step, a screenshot
    /// (`screenshotKey`: P this frame), a recorded frame.
    void requestReadbacks(ViewerSession& session, ViewerUi& ui, bool screenshotKey);
    /// Whether this frame's screenshot waits for the panel to be drawn over the scene.
    bool panelShotPending() const { return m_panelShotPending; }
    /// Queues a copy of the window's back buffer (scene, panel and help) as a screenshot.
    void requestWindowScreenshot(glm::uvec2 size, std::uint64_t step);
    /// Writes the frames whose readback finished; `wait` for all of them.
    void writeReadbacks(bool wait, ViewerSession& session, ViewerUi& ui);
    /// At exit: every readback written, the recording and the capture finished; a
    /// --screenshot-at step the window never showed is an error (failed()).
    void finish(ViewerSession& session, ViewerUi& ui);
    /// Whether a --frames, --video or --screenshot-at output failed or was never written (the
    /// exit code says so).
    bool failed() const { return m_failed; }

private:
    // Why a frame is read back (requests come back in order, so these queue beside them).
    struct Purpose {
        bool capture = false; // --frames / --video
        bool screenshot = false;
        bool record = false;
    };

    void screenshot(const ReadbackFrame& frame, ViewerSession& session, ViewerUi& ui);

    const ViewerOptions& m_options;
    FrameReadback m_readback{3};
    std::deque<Purpose> m_purposes;
    std::optional<FrameCapture> m_capture;
    std::optional<VideoEncoder> m_recording;
    glm::uvec2 m_recordSize{0};
    std::uint64_t m_lastCaptured = ~std::uint64_t{0};
    std::uint64_t m_lastRecorded = ~std::uint64_t{0};
    bool m_failed = false;
    bool m_shotAtTaken = false;   ///< the --screenshot-at readback was requested
    bool m_shotAtWritten = false; ///< and its file written
    bool m_panelShotPending = false;
};

} // namespace sluice::rt
