// Video capture: rendered frames piped as raw RGB to an ffmpeg process that encodes H.264 MP4.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <glm/glm.hpp>
#include <sys/types.h>

#include "sluice/format/support/Result.h"
#include "sluice/rt/render/Image.h"

namespace sluice::rt {

/// The ffmpeg program the encoder runs: the environment variable SLUICE_FFMPEG when set (a path
/// to the program), else the first executable `ffmpeg` on PATH. Unsupported, saying how to
/// install it, when there is none.
Result<std::filesystem::path> findFfmpeg();

/// One ffmpeg process encoding one MP4 file. The file appears only when finish() succeeds: until
/// then ffmpeg writes a temporary file in the same folder. RAII, move-only; destroying an
/// unfinished encoder stops ffmpeg and removes the temporary file.
class VideoEncoder {
public:
    /// Starts `ffmpeg` (see findFfmpeg) for frames of `size` pixels shown at `fps` frames per
    /// second, H.264 (libx264, yuv420p; odd sizes are padded by a pixel). Unsupported without
    /// ffmpeg; Io when the folder of `path` does not exist or ffmpeg cannot be started.
    static Result<VideoEncoder> start(const std::filesystem::path& path, glm::uvec2 size,
                                      double fps);

    VideoEncoder(VideoEncoder&& other) noexcept;
    VideoEncoder& operator=(VideoEncoder&& other) noexcept;
    VideoEncoder(const VideoEncoder&) = delete;
    VideoEncoder& operator=(const VideoEncoder&) = delete;
    ~VideoEncoder();

    /// Sends one frame. Precondition: the size given to start(). Io (with the end of ffmpeg's
    /// log) if ffmpeg stopped taking frames.
    Result<void> write(const Image& frame);

    /// Closes the pipe, waits for ffmpeg and moves the file into place. Io with the end of
    /// ffmpeg's log if it failed; the target is then left as it was.
    Result<void> finish();

    const std::filesystem::path& path() const { return m_path; }
    std::uint64_t frames() const { return m_frames; }

private:
    VideoEncoder() = default;
    /// Closes the pipe and waits for ffmpeg; its exit status, or -1.
    int stop();
    std::string logTail() const;
    void release();

    std::filesystem::path m_path;
    std::filesystem::path m_temp;
    std::filesystem::path m_log;
    glm::uvec2 m_size{0};
    int m_pipe = -1; // write end of ffmpeg's stdin
    pid_t m_pid = -1;
    std::uint64_t m_frames = 0;
};

} // namespace sluice::rt
