// The viewer's captures, screenshots and recording (ViewerOutputs.h).
#include "viewer/ViewerOutputs.h"

#include <algorithm>
#include <ctime>
#include <filesystem>
#include <iostream>

#include "sluice/rt/render/Image.h"

namespace sluice::rt {
namespace {

// Frames per second [Hz] of a video that plays the simulation in real time.
double realTimeFps(const format::Scene& scene, std::uint32_t stepsPerFrame) {
    return 1.0 / (double(scene.simulation.timeStep) * double(std::max(stepsPerFrame, 1u)));
}

} // namespace

void reportStatus(ViewerUi& ui, const Result<void>& result, const std::string& done) {
    ui.status = result ? done : result.error().message();
    if (!result)
        std::cerr << "sluice-play: " << result.error().message() << '\n';
}

Result<void> ViewerOutputs::start(ViewerSession& session) {
    if (m_options.capture.frames()) {
        auto capture = FrameCapture::start(m_options.capture, session.renderer().size(),
                                           session.scene().simulation.timeStep);
        if (!capture)
            return capture.error();
        m_capture.emplace(std::move(*capture));
    }
    return createShotsFolder(m_options.capture);
}

void ViewerOutputs::toggleRecording(ViewerSession& session, ViewerUi& ui) {
    if (m_recording) {
        const std::string path = m_recording->path().string();
        writeReadbacks(true, session, ui);
        reportStatus(ui, m_recording->finish(), "saved " + path);
        m_recording.reset();
        ui.recording = false;
        return;
    }
    char stamp[32];
    const std::time_t now = std::time(nullptr);
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
    const std::string path = session.scene().name + "-" + stamp + ".mp4";
    auto encoder =
        VideoEncoder::start(path, session.renderer().size(),
                            realTimeFps(session.scene(), std::uint32_t(ui.stepsPerFrame)));
    if (!encoder) {
        reportStatus(ui, encoder.error(), "");
        return;
    }
    m_recording.emplace(std::move(*encoder));
    m_recordSize = session.renderer().size();
    ui.recording = true;
    ui.status = "recording " + path;
}

void ViewerOutputs::requestReadbacks(ViewerSession& session, ViewerUi& ui, bool screenshotKey) {
    const std::uint64_t step = session.steps();
    Purpose purpose;
    if (m_capture && m_capture->wants(step) && step != m_lastCaptured) {
        purpose.capture = true;
        m_lastCaptured = step;
    }
    bool screenshot = screenshotKey;
    if (m_options.capture.screenshotAt == step && !m_shotAtTaken) {
        screenshot = true;
        m_shotAtTaken = true;
    }
    // A screenshot with the panel reads the window's back buffer once the panel is drawn.
    purpose.screenshot = screenshot && !ui.screenshotPanel;
    m_panelShotPending = screenshot && ui.screenshotPanel;
    if (m_recording && step != m_lastRecorded) {
        if (session.renderer().size() == m_recordSize) {
            purpose.record = true;
            m_lastRecorded = step;
        } else {
            reportStatus(ui, m_recording->finish(),
                         "the window changed size: recording stopped, saved " +
                             m_recording->path().string());
            m_recording.reset();
            ui.recording = false;
        }
    }
    if (!purpose.capture && !purpose.screenshot && !purpose.record)
        return;
    const Renderer& renderer = session.renderer();
    m_readback.request(renderer.outputFramebuffer(), renderer.size(), step);
    m_purposes.push_back(purpose);
}

void ViewerOutputs::requestWindowScreenshot(glm::uvec2 size, std::uint64_t step) {
    m_readback.request(0, size, step);
    Purpose purpose;
    purpose.screenshot = true;
    m_purposes.push_back(purpose);
    m_panelShotPending = false;
}

void ViewerOutputs::writeReadbacks(bool wait, ViewerSession& session, ViewerUi& ui) {
    for (ReadbackFrame& frame : m_readback.collect(wait)) {
        const Purpose purpose = m_purposes.front();
        m_purposes.pop_front();
        if (purpose.capture && m_capture) {
            if (auto ok = m_capture->write(frame.tag, frame.image); !ok) {
                reportStatus(ui, ok, "");
                m_capture.reset();
                m_failed = true;
            }
        }
        if (purpose.screenshot)
            screenshot(frame, session, ui);
        if (purpose.record && m_recording) {
            if (auto ok = m_recording->write(frame.image); !ok) {
                reportStatus(ui, ok, "");
                m_recording.reset();
                ui.recording = false;
            }
        }
    }
}

void ViewerOutputs::screenshot(const ReadbackFrame& frame, ViewerSession& session, ViewerUi& ui) {
    const std::filesystem::path path =
        screenshotPath(m_options.capture.shotsDir, session.scene().name, frame.tag);
    const Result<void> written = writePng(path, frame.image);
    reportStatus(ui, written, "saved " + path.string());
    if (m_options.capture.screenshotAt != frame.tag)
        return;
    if (!written) {
        m_failed = true;
        return;
    }
    m_shotAtWritten = true;
    if (!m_options.quiet)
        std::cout << "sluice-play: screenshot " << path.string() << '\n';
}

void ViewerOutputs::finish(ViewerSession& session, ViewerUi& ui) {
    writeReadbacks(true, session, ui);
    if (m_options.capture.screenshotAt && !m_shotAtWritten && !m_failed) {
        // The window closed (or --max-frames ended it) before showing that step: the run
        // fails rather than ending as if the picture were there.
        std::cerr << "sluice-play: --screenshot-at " << *m_options.capture.screenshotAt
                  << ": no screenshot was written: the window closed before showing that step "
                     "(at step "
                  << session.steps() << ")\n";
        m_failed = true;
    }
    if (m_recording) {
        reportStatus(ui, m_recording->finish(), "saved " + m_recording->path().string());
        if (!m_options.quiet)
            std::cout << "sluice-play: " << ui.status << '\n';
        m_recording.reset();
    }
    if (!m_capture)
        return;
    if (auto ok = m_capture->finish(); !ok) {
        reportStatus(ui, ok, "");
        m_failed = true;
    } else if (!m_options.quiet) {
        std::cout << "sluice-play: captured " << m_capture->framesWritten() << " frames";
        if (!m_options.capture.framesDir.empty())
            std::cout << " into " << m_options.capture.framesDir;
        if (!m_options.capture.video.empty())
            std::cout << " and " << m_options.capture.video;
        std::cout << '\n';
    }
    m_capture.reset();
}

} // namespace sluice::rt
