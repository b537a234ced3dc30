// Headless capture: render on the captured steps, read back through the fence ring, write.
#include "capture/CaptureHeadless.h"

#include <ostream>

#include "sluice/rt/sim/Simulation.h"
#include "sluice/rt/render/Image.h"
#include "sluice/rt/render/SceneFraming.h"

namespace sluice::rt {

HeadlessCapture::HeadlessCapture(Renderer renderer, OrbitCamera camera)
    : m_renderer(std::move(renderer)), m_camera(camera) {}

Result<HeadlessCapture> HeadlessCapture::start(const format::Scene& scene,
                                               const std::vector<format::ColliderAsset>& colliders,
                                               const CaptureOptions& options, glm::uvec2 size,
                                               const RenderSettings& settings) {
    std::optional<FrameCapture> frames;
    if (options.frames()) {
        auto started = FrameCapture::start(options, size, scene.simulation.timeStep);
        if (!started)
            return started.error();
        frames.emplace(std::move(*started));
    }
    if (auto ok = createShotsFolder(options); !ok)
        return ok.error();
    auto renderer = Renderer::create(scene, colliders, size);
    if (!renderer)
        return renderer.error();
    OrbitCamera camera = sceneCamera(scene, renderer->bounds(), float(size.x) / float(size.y));
    camera.zoom(options.zoom);
    HeadlessCapture capture(std::move(*renderer), camera);
    capture.m_settings = settings;
    capture.m_options = options;
    capture.m_sceneName = scene.name;
    capture.m_frames = std::move(frames);
    return capture;
}

Result<void> HeadlessCapture::afterStep(const Simulation& sim, std::uint64_t step) {
    Pending pending;
    pending.frame = m_frames && m_frames->wants(step);
    pending.screenshot = m_options.screenshotAt == step;
    if (!pending.frame && !pending.screenshot)
        return {};
    m_renderer.render(sim, m_camera, m_settings);
    m_readback.request(m_renderer.outputFramebuffer(), m_renderer.size(), step);
    ++m_rendered;
    m_pending.push_back(pending);
    return writeReady(false);
}

Result<void> HeadlessCapture::writeReady(bool wait) {
    for (ReadbackFrame& frame : m_readback.collect(wait)) {
        const Pending pending = m_pending.front();
        m_pending.pop_front();
        if (pending.frame) {
            if (auto ok = m_frames->write(frame.tag, frame.image); !ok)
                return ok;
        }
        if (pending.screenshot) {
            const auto path = screenshotPath(m_options.shotsDir, m_sceneName, frame.tag);
            if (auto ok = writePng(path, frame.image); !ok)
                return ok;
            m_screenshots.push_back(path.string());
        }
    }
    return {};
}

Result<void> HeadlessCapture::finish() {
    if (auto ok = writeReady(true); !ok)
        return ok;
    if (m_frames) {
        if (auto ok = m_frames->finish(); !ok)
            return ok;
    }
    return {};
}

void HeadlessCapture::report(std::ostream& out) const {
    const glm::uvec2 size = m_renderer.size();
    const std::uint64_t count = m_frames ? m_frames->framesWritten() : 0;
    out << "rendered " << m_rendered << " frames of " << size.x << "x" << size.y << "\n";
    if (!m_options.framesDir.empty())
        out << "  frames:     " << count << " in " << m_options.framesDir << "/frame_NNNNNN.png\n";
    if (!m_options.video.empty())
        out << "  video:      " << m_options.video << " (" << count << " frames, "
            << (m_frames ? m_frames->fps() : 0.0) << " frames/s)\n";
    for (const std::string& shot : m_screenshots)
        out << "  screenshot: " << shot << "\n";
}

} // namespace sluice::rt
