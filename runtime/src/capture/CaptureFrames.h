// What a run captures: PNG files of every K-th step into a folder and/or one MP4 video, from
// frames the renderer read back. Shared by the headless runs and the viewer window.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <glm/glm.hpp>

#include "capture/CaptureVideo.h"
#include "sluice/format/support/Result.h"
#include "sluice/rt/render/Image.h"

namespace sluice::rt {

/// The capture flags of sluice-play.
struct CaptureOptions {
    std::string framesDir;   ///< --frames: write frame_STEP.png files here (created)
    std::uint64_t every = 1; ///< --every: capture steps 0, K, 2K, ...
    std::string video;       ///< --video: one MP4 of the captured frames
    double fps = 0.0;        ///< --fps: frames per second of the video; 0: real time,
                             ///< 1 / (every * timeStep)
    std::optional<std::uint64_t> screenshotAt; ///< --screenshot-at: one PNG of this step
    std::string shotsDir; ///< --shots: folder of screenshots (default: the working folder)
    float zoom = 1.0f;    ///< --zoom: the camera's distance times this (< 1: closer)

    /// Whether frames or a video are asked for (screenshots aside).
    bool frames() const { return !framesDir.empty() || !video.empty(); }
    /// Whether anything at all is to be rendered and written.
    bool any() const { return frames() || screenshotAt.has_value(); }
};

/// "WIDTHxHEIGHT" (e.g. "1280x720") as pixels. InvalidArgument naming the text when it is not
/// two positive integers up to kMaxImageSide (Renderer.h) joined by 'x'.
Result<glm::uvec2> parseImageSize(std::string_view text);

/// "frame_000012.png" for step 12.
std::string pngFrameName(std::uint64_t step);

/// Where a screenshot of step `step` goes: `folder`/NAME-STEP.png (six digits), with -2, -3, ...
/// before ".png" when that file exists already. An empty folder is the working folder.
std::filesystem::path screenshotPath(const std::string& folder, const std::string& sceneName,
                                     std::uint64_t step);

/// Creates the screenshot folder of `options` (--shots) if one is named. Io naming it when it
/// cannot be created.
Result<void> createShotsFolder(const CaptureOptions& options);

/// Writes the captured frames of one run. Move-only.
class FrameCapture {
public:
    /// Starts ffmpeg and creates the frames folder as the options ask, for frames of `size`
    /// pixels; `timeStep` [s] sets the real-time frame rate. Unsupported when a video is asked
    /// for and there is no ffmpeg (nothing is created then); Io when the folder cannot be
    /// created.
    static Result<FrameCapture> start(const CaptureOptions& options, glm::uvec2 size,
                                      double timeStep);

    /// Whether step `step` is one to capture.
    bool wants(std::uint64_t step) const { return step % m_options.every == 0; }

    /// Writes the frame of step `step`: its PNG file and/or the next video frame.
    Result<void> write(std::uint64_t step, const Image& image);

    /// Finishes the video (if any). Call once, after the last write.
    Result<void> finish();

    std::uint64_t framesWritten() const { return m_frames; }
    double fps() const { return m_fps; }
    const CaptureOptions& options() const { return m_options; }

private:
    FrameCapture() = default;

    CaptureOptions m_options;
    std::optional<VideoEncoder> m_video;
    double m_fps = 0.0;
    std::uint64_t m_frames = 0;
};

} // namespace sluice::rt
