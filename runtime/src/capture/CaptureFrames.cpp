// Frame schedules, size parsing and the PNG + video fan-out of captured frames.
#include "capture/CaptureFrames.h"

#include <charconv>
#include <cstdio>
#include <system_error>

#include "sluice/rt/render/Image.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {
namespace fs = std::filesystem;

Result<glm::uvec2> parseImageSize(std::string_view text) {
    const auto bad = [&] {
        return fail(ErrorCode::InvalidArgument,
                    "--size " + std::string(text) + ": expected WIDTHxHEIGHT in pixels, each 1.." +
                        std::to_string(kMaxImageSide) + " (e.g. 1280x720)");
    };
    const std::size_t x = text.find('x');
    if (x == std::string_view::npos)
        return bad();
    glm::uvec2 size{0};
    const std::string_view parts[2] = {text.substr(0, x), text.substr(x + 1)};
    for (int i = 0; i < 2; ++i) {
        const std::string_view part = parts[i];
        if (part.empty())
            return bad();
        const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), size[i]);
        if (ec != std::errc() || end != part.data() + part.size() || size[i] == 0 ||
            size[i] > kMaxImageSide)
            return bad();
    }
    return size;
}

std::string pngFrameName(std::uint64_t step) {
    char name[40];
    std::snprintf(name, sizeof name, "frame_%06llu.png", static_cast<unsigned long long>(step));
    return name;
}

fs::path screenshotPath(const std::string& folder, const std::string& sceneName,
                        std::uint64_t step) {
    char digits[32];
    std::snprintf(digits, sizeof digits, "-%06llu", static_cast<unsigned long long>(step));
    const fs::path dir = folder.empty() ? fs::path(".") : fs::path(folder);
    fs::path path = dir / (sceneName + digits + ".png");
    std::error_code ec;
    for (int n = 2; fs::exists(path, ec); ++n)
        path = dir / (sceneName + digits + "-" + std::to_string(n) + ".png");
    return folder.empty() ? path.lexically_relative(".") : path;
}

Result<void> createShotsFolder(const CaptureOptions& options) {
    if (options.shotsDir.empty())
        return {};
    std::error_code ec;
    fs::create_directories(options.shotsDir, ec);
    if (ec)
        return fail(ErrorCode::Io,
                    options.shotsDir + ": cannot create the screenshot folder: " + ec.message());
    return {};
}

Result<FrameCapture> FrameCapture::start(const CaptureOptions& options, glm::uvec2 size,
                                         double timeStep) {
    FrameCapture capture;
    capture.m_options = options;
    if (capture.m_options.every == 0)
        capture.m_options.every = 1;
    capture.m_fps =
        options.fps > 0.0 ? options.fps : 1.0 / (double(capture.m_options.every) * timeStep);
    if (!options.video.empty()) {
        auto video = VideoEncoder::start(options.video, size, capture.m_fps);
        if (!video)
            return video.error();
        capture.m_video.emplace(std::move(*video));
    }
    if (!options.framesDir.empty()) {
        std::error_code ec;
        fs::create_directories(options.framesDir, ec);
        if (ec)
            return fail(ErrorCode::Io,
                        options.framesDir + ": cannot create the frames folder: " + ec.message());
    }
    return capture;
}

Result<void> FrameCapture::write(std::uint64_t step, const Image& image) {
    if (!m_options.framesDir.empty()) {
        if (auto ok = writePng(fs::path(m_options.framesDir) / pngFrameName(step), image); !ok)
            return ok;
    }
    if (m_video) {
        if (auto ok = m_video->write(image); !ok)
            return ok;
    }
    ++m_frames;
    return {};
}

Result<void> FrameCapture::finish() {
    if (!m_video)
        return {};
    auto ok = m_video->finish();
    m_video.reset();
    return ok;
}

} // namespace sluice::rt
