// The viewer window: GLFW set-up, input to camera, actions and the body drag, and the frame loop
// (render, present with the panel, collect finished readbacks, step). Nothing in a frame waits
// for the GPU but the dynamic bodies' poses: statistics, timers and captured frames
// (ViewerOutputs) all come back through fences a few frames later.
#include "viewer/Viewer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <deque>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "sluice/gpu/Gl.h" // glad first: GLFW must not include the system GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "capture/CaptureVideo.h"
#include "play/Interrupt.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/play/PlayCli.h"
#include "sluice/rt/render/FluidStatsProbe.h"
#include "sluice/rt/render/FrameReadback.h"
#include "sluice/rt/render/Image.h"
#include "sluice/rt/render/SceneFraming.h"
#include "viewer/ViewerBodies.h"
#include "viewer/ViewerInput.h"
#include "viewer/ViewerOutputs.h"
#include "viewer/ViewerPanel.h"
#include "viewer/ViewerPick.h"
#include "viewer/ViewerSession.h"

namespace sluice::rt {
namespace {

using Clock = std::chrono::steady_clock;

std::string g_glfwError; // the latest message of GLFW's error callback

void onGlfwError(int, const char* text) {
    g_glfwError = text != nullptr ? text : "unknown GLFW error";
}

// glfwTerminate on every way out of runViewer once glfwInit succeeded.
struct GlfwLibrary {
    GlfwLibrary() = default;
    GlfwLibrary(const GlfwLibrary&) = delete;
    GlfwLibrary& operator=(const GlfwLibrary&) = delete;
    ~GlfwLibrary() {
        gpu::keepDriverLoadedForLeakChecks(); // ASan builds: glfwTerminate would unload it
        glfwTerminate();
    }
};

class ViewerApp final : public ViewerControl {
public:
    ViewerApp(GLFWwindow* window, const ViewerOptions& options, ViewerSession session)
        : m_window(window), m_options(options), m_session(std::move(session)) {
        m_ui.showPanel = options.panel;
        m_ui.screenshotPanel = options.screenshotPanel;
        m_ui.stepsPerFrame = std::int32_t(options.stepsPerFrame);
        m_ui.render = options.settings;
        m_ui.params = m_session->scene().simulation;
        const glm::uvec2 size = m_session->renderer().size();
        m_camera = sceneCamera(m_session->scene(), m_session->renderer().bounds(),
                               float(size.x) / float(size.y));
        m_camera.zoom(options.capture.zoom);
        glfwSetWindowUserPointer(window, this);
        glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int code, int action, int mods) {
            ImGui_ImplGlfw_KeyCallback(w, key, code, action, mods);
            ViewerApp& app = of(w);
            if (!ImGui::GetIO().WantCaptureKeyboard)
                app.m_input.key(key, action, mods, app.m_ui, app.m_actions);
        });
        glfwSetCharCallback(window, ImGui_ImplGlfw_CharCallback);
        glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
            ImGui_ImplGlfw_MouseButtonCallback(w, button, action, mods);
            glm::dvec2 cursor(0.0);
            glfwGetCursorPos(w, &cursor.x, &cursor.y);
            of(w).mouseButton(button, action, mods, cursor);
        });
        glfwSetScrollCallback(window, [](GLFWwindow* w, double dx, double dy) {
            ImGui_ImplGlfw_ScrollCallback(w, dx, dy);
            if (!ImGui::GetIO().WantCaptureMouse)
                of(w).m_camera.zoom(ViewerInput::zoomFactor(dy));
        });
        glfwSetCursorPosCallback(
            window, [](GLFWwindow* w, double x, double y) { of(w).moveCursor(glm::dvec2(x, y)); });
        glfwSetWindowFocusCallback(window, ImGui_ImplGlfw_WindowFocusCallback);
        glfwSetCursorEnterCallback(window, ImGui_ImplGlfw_CursorEnterCallback);
    }

    ViewerApp(const ViewerApp&) = delete;
    ViewerApp& operator=(const ViewerApp&) = delete;

    ~ViewerApp() override {
        glfwSetWindowUserPointer(m_window, nullptr);
        glfwSetKeyCallback(m_window, nullptr);
        glfwSetMouseButtonCallback(m_window, nullptr);
        glfwSetScrollCallback(m_window, nullptr);
        glfwSetCursorPosCallback(m_window, nullptr);
        glfwSetCharCallback(m_window, nullptr);
        glfwSetWindowFocusCallback(m_window, nullptr);
        glfwSetCursorEnterCallback(m_window, nullptr);
    }

    // Runs until the window closes or --max-frames; the exit code.
    int run() {
        if (auto ok = m_outputs.start(*m_session); !ok) {
            std::cerr << "sluice-play: " << ok.error().message() << '\n';
            return exitCodeFor(ok.error());
        }
        auto probe = FluidStatsProbe::create();
        if (!probe) {
            std::cerr << "sluice-play: " << probe.error().message() << '\n';
            return exitCodeFor(probe.error());
        }
        m_probe.emplace(std::move(*probe));

        const Clock::time_point start = Clock::now();
        Clock::time_point last = start;
        while (!glfwWindowShouldClose(m_window) && !m_actions.quit &&
               !InterruptGuard::requested()) {
            glfwPollEvents();
            frame();
            ++m_frames;
            const Clock::time_point now = Clock::now();
            const double ms = std::chrono::duration<double, std::milli>(now - last).count();
            m_frameMs = m_frames == 1 ? ms : 0.9 * m_frameMs + 0.1 * ms;
            last = now;
            measureStepRate(now);
            if (m_options.maxFrames > 0 && m_frames >= m_options.maxFrames)
                break;
        }
        m_outputs.finish(*m_session, m_ui);
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        if (!m_options.quiet)
            std::cout << "sluice-play: " << m_frames << " frames, " << m_session->steps()
                      << " steps in " << seconds << " s (" << double(m_frames) / seconds
                      << " frames/s)\n";
        if (InterruptGuard::requested()) {
            std::cerr << "sluice-play: " << InterruptGuard::signalName()
                      << ": the window closed at step " << m_session->steps()
                      << "; its captures were written up to it\n";
            return InterruptGuard::exitCode();
        }
        return m_outputs.failed() ? kExitBadInput : kExitOk;
    }

    // ViewerControl: the GLFW callbacks call these too.
    std::uint64_t frames() const override { return m_frames; }

    void mouseButton(int button, int action, int mods, glm::dvec2 cursor) override {
        // A press on the panel is the panel's; a release always ends a drag.
        if (action != GLFW_PRESS || !ImGui::GetIO().WantCaptureMouse)
            m_input.mouseButton(button, action, mods, cursor);
    }

    void moveCursor(glm::dvec2 cursor) override {
        m_input.cursor(cursor.x, cursor.y, int(windowSize().y), m_camera);
    }

    glm::uvec2 windowSize() const override {
        int width = 0;
        int height = 0;
        glfwGetWindowSize(m_window, &width, &height);
        return glm::uvec2(std::max(width, 0), std::max(height, 0));
    }

    const OrbitCamera& camera() const override { return m_camera; }
    ViewerSession& session() override { return *m_session; }
    ViewerUi& ui() override { return m_ui; }

private:
    static ViewerApp& of(GLFWwindow* window) {
        return *static_cast<ViewerApp*>(glfwGetWindowUserPointer(window));
    }

    void frame() {
        if (m_options.script)
            m_options.script(*this);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        updateBodies();
        if (m_ui.showPanel)
            drawViewerPanel(m_ui, figures(), m_actions);
        if (m_ui.showHelp)
            drawViewerHelp(m_ui.showHelp);
        if (m_session->grab())
            drawDragMarker(*m_session->grab(), m_bodies, m_camera, windowSize());
        ImGui::Render();
        handleActions();

        int width = 0;
        int height = 0;
        glfwGetFramebufferSize(m_window, &width, &height);
        if (width > 0 && height > 0) {
            if (auto ok = m_session->renderer().resize(glm::uvec2(width, height)); !ok)
                m_ui.status = ok.error().message();
            Renderer& renderer = m_session->renderer();
            renderer.render(m_session->simulation(), m_camera, m_ui.render);
            m_outputs.requestReadbacks(*m_session, m_ui, m_actions.screenshot);
            if (m_frames % 8 == 0)
                m_probe->record(m_session->simulation());
            if (auto stats = m_probe->poll())
                m_fluid = stats;
            m_renderGpuMs = renderer.gpuMilliseconds();
            m_renderPassMs = renderer.passTimes();
            glBlitNamedFramebuffer(renderer.outputFramebuffer(), 0, 0, 0, width, height, 0, 0,
                                   width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            glViewport(0, 0, width, height);
        }
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (m_outputs.panelShotPending() && width > 0 && height > 0)
            m_outputs.requestWindowScreenshot(glm::uvec2(width, height), m_session->steps());
        glfwSwapBuffers(m_window);
        m_outputs.writeReadbacks(false, *m_session, m_ui);

        if (!m_ui.paused) {
            for (std::int32_t i = 0; i < m_ui.stepsPerFrame; ++i)
                m_session->step();
        } else if (m_actions.step) {
            m_session->step();
        }
        m_actions = {};
    }

    ViewerFigures figures() {
        ViewerFigures f;
        const Simulation& sim = m_session->simulation();
        f.sceneName = m_session->scene().name;
        f.particles = sim.particleCount();
        f.capacity = sim.capacity();
        f.steps = m_session->steps();
        f.time = m_session->time();
        f.stepsPerSecond = m_stepsPerSecond;
        f.frameMs = m_frameMs;
        f.renderGpuMs = m_renderGpuMs;
        f.renderPassMs = m_renderPassMs;
        f.passMs = m_session->simulation().passTimes();
        f.fluid = m_fluid;
        f.hasEmitters = !m_session->scene().emitters.empty();
        if (m_session->hasBodies())
            f.bodies = m_readout.rows();
        if (m_session->grab())
            f.heldBody = m_session->grab()->body;
        return f;
    }

    // The ray under the cursor; nullopt while the window has no area (minimised).
    std::optional<Ray> rayUnderCursor() const {
        const glm::uvec2 size = windowSize();
        if (size.x == 0 || size.y == 0)
            return std::nullopt;
        return cursorRay(m_camera, m_input.cursorPosition(), glm::dvec2(size));
    }

    // The mouse spring follows the input: a Ctrl + left press picks, the held button drags (the
    // target follows the cursor and the camera), the release lets go. The spring only acts in
    // steps, so while paused the body waits. Then the bodies are read for the panel and the
    // marker (a small sync; the renderer waits for their poses anyway).
    void updateBodies() {
        ViewerSession& session = *m_session;
        const std::optional<Ray> ray = rayUnderCursor();
        if (m_input.takeGrabRequest() && m_input.draggingBody() && ray) {
            if (!session.hasBodies())
                m_ui.status = "this scene has no dynamic bodies to pull";
            else if (const auto hit = session.grabBody(*ray))
                m_ui.status = "holding body " + std::to_string(hit->body);
            else
                m_ui.status = "no body under the cursor";
        }
        if (session.grab() && !m_input.draggingBody())
            session.releaseBody();
        if (session.grab() && ray)
            session.dragBody(*ray);
        m_bodies.clear();
        if (session.hasBodies() && (m_ui.showPanel || session.grab())) {
            m_bodies = session.simulation().bodies();
            m_readout.update(session.scene(), m_bodies, session.time());
        }
    }

    void measureStepRate(Clock::time_point now) {
        const double seconds = std::chrono::duration<double>(now - m_rateStart).count();
        if (seconds < 0.5)
            return;
        const std::uint64_t steps = m_session->steps();
        m_stepsPerSecond = steps >= m_rateSteps ? double(steps - m_rateSteps) / seconds : 0.0;
        m_rateStart = now;
        m_rateSteps = steps;
    }

    void report(const Result<void>& result, const std::string& done) {
        reportStatus(m_ui, result, done);
    }

    void handleActions() {
        ViewerActions& a = m_actions;
        if (a.reset)
            report(m_session->reset(), "reset");
        if (a.reload) {
            report(m_session->reload(), "reloaded " + m_session->scene().path);
            m_ui.params = m_session->scene().simulation;
            m_ui.emitters = m_session->emittersEnabled();
        }
        if (a.applyParameters) {
            report(m_session->applyParameters(m_ui.params), "parameters applied");
            m_ui.params = m_session->scene().simulation; // what runs, after a refusal too
        }
        if (a.emitters) {
            m_session->setEmittersEnabled(*a.emitters);
            m_ui.status = *a.emitters ? "emitters on" : "emitters off";
        }
        if (a.frame) {
            const glm::uvec2 size = m_session->renderer().size();
            m_camera.frame(m_session->renderer().bounds(), float(size.x) / float(size.y));
        }
        if (a.toggleRecording)
            m_outputs.toggleRecording(*m_session, m_ui);
    }

    GLFWwindow* m_window;
    const ViewerOptions& m_options;
    std::optional<ViewerSession> m_session;
    OrbitCamera m_camera;
    ViewerUi m_ui;
    ViewerActions m_actions;
    std::optional<FluidStatsProbe> m_probe;
    std::optional<FluidStats> m_fluid;
    std::optional<double> m_renderGpuMs;
    RenderPassTimes m_renderPassMs = [] {
        RenderPassTimes unknown;
        unknown.fill(-1.0);
        return unknown;
    }();
    ViewerOutputs m_outputs{m_options};
    std::uint64_t m_frames = 0;
    double m_frameMs = 0.0;
    double m_stepsPerSecond = 0.0;
    Clock::time_point m_rateStart = Clock::now();
    std::uint64_t m_rateSteps = 0;
    ViewerInput m_input;
    std::vector<BodyState> m_bodies; // read this frame; empty when not needed
    BodyReadout m_readout;
};

// ImGui's context and backends for one window (RAII).
struct ImGuiScope {
    explicit ImGuiScope(GLFWwindow* window) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr; // no imgui.ini left in the working folder
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(window, false);
        ImGui_ImplOpenGL3_Init("#version 450");
    }
    ImGuiScope(const ImGuiScope&) = delete;
    ImGuiScope& operator=(const ImGuiScope&) = delete;
    ~ImGuiScope() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
};

} // namespace

int runViewer(const ViewerOptions& options) {
    const InterruptGuard interrupt;
    glfwSetErrorCallback(onGlfwError);
    if (glfwInit() != GLFW_TRUE) {
        std::cerr << "sluice-play: cannot open a window: " << g_glfwError
                  << "\n  Without a display, run headless: sluice-play SCENE --headless --steps N"
                     " [--frames DIR] [--video OUT.mp4]\n";
        return kExitNoGlContext;
    }
    GlfwLibrary glfw;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    const std::string title = "Sluice - " + std::filesystem::path(options.scene).stem().string();
    GLFWwindow* window =
        glfwCreateWindow(int(options.size.x), int(options.size.y), title.c_str(), nullptr, nullptr);
    if (window == nullptr) {
        std::cerr << "sluice-play: cannot create a window with an OpenGL 4.5 core context: "
                  << g_glfwError << "\n  Run headless instead: sluice-play SCENE --headless\n";
        return kExitNoGlContext;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(options.vsync ? 1 : 0);
    const int version = sluice_gladLoadGL(reinterpret_cast<GLADloadfunc>(glfwGetProcAddress));
    if (version == 0 || GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 45) {
        std::cerr << "sluice-play: the window's OpenGL context is not 4.5 core\n";
        glfwDestroyWindow(window);
        return kExitNoGlContext;
    }
    int exitCode = kExitOk;
    {
        ImGuiScope imgui(window);
        int width = 0;
        int height = 0;
        glfwGetFramebufferSize(window, &width, &height);
        auto session = ViewerSession::open(options.scene, options.deterministic,
                                           glm::uvec2(std::max(width, 1), std::max(height, 1)));
        if (!session) {
            std::cerr << "sluice-play: " << session.error().message() << '\n';
            exitCode = exitCodeFor(session.error());
        } else {
            ViewerApp app(window, options, std::move(*session));
            exitCode = app.run();
        }
    }
    glfwDestroyWindow(window);
    return exitCode;
}

} // namespace sluice::rt
