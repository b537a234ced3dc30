// The ImGui panel: simulation parameters applied when an edit ends, render modes, statistics,
// the dynamic bodies.
#include "viewer/ViewerPanel.h"

#include <algorithm>

#include <imgui.h>

namespace sluice::rt {
namespace {

// The labels beside sliders; the widest one sets the panel's width.
constexpr const char* kSliderLabels[] = {
    "steps per frame",   "min iterations",    "max iterations",
    "target error",      "relaxation (eps)",  "s_corr k",
    "s_corr n",          "s_corr dq [m]",     "XSPH c",
    "vorticity [m/s]",   "gravity [m/s2]",    "time step [ms]",
    "substeps",          "speed range [m/s]", "error range",
    "smoothing passes",  "filter radius [r]", "absorption [1/m]",
    "refraction [px/m]",
};

float widestLabel() {
    float widest = 0.0f;
    for (const char* label : kSliderLabels)
        widest = std::max(widest, ImGui::CalcTextSize(label).x);
    return widest;
}

// True when the widget just finished an edit (slider released, text committed): parameters are
// applied then, not on every drag frame, since applying rebuilds the simulation.
bool edited() {
    return ImGui::IsItemDeactivatedAfterEdit();
}

void statistics(const ViewerFigures& f) {
    // Wrapped: the panel is narrow in small windows.
    ImGui::TextWrapped("%s: %u particles (capacity %u)", f.sceneName.c_str(), f.particles,
                       f.capacity);
    ImGui::TextWrapped("step %llu, t = %.3f s", static_cast<unsigned long long>(f.steps), f.time);
    ImGui::TextWrapped("%.1f steps/s, frame %.2f ms", f.stepsPerSecond, f.frameMs);
    if (f.renderGpuMs)
        ImGui::TextWrapped("render GPU %.2f ms", *f.renderGpuMs);
    if (f.fluid)
        ImGui::TextWrapped("density error avg %.3f %%, max %.2f %%; max speed %.2f m/s",
                           100.0 * f.fluid->avgDensityError, 100.0 * f.fluid->maxDensityError,
                           f.fluid->maxSpeed);
    if (ImGui::BeginTable("passes", 2, ImGuiTableFlags_SizingStretchProp)) {
        double total = 0.0;
        for (std::size_t p = 0; p < f.passMs.size(); ++p) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(passName(Pass(p)));
            ImGui::TableNextColumn();
            if (f.passMs[p] >= 0.0) {
                ImGui::Text("%.3f ms", f.passMs[p]);
                total += f.passMs[p];
            } else {
                ImGui::TextUnformatted("-");
            }
        }
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted("step GPU");
        ImGui::TableNextColumn();
        ImGui::Text("%.3f ms", total);
        for (std::size_t p = 0; p < f.renderPassMs.size(); ++p) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            // The screen-space surface's stages are parts of "render fluid".
            const bool stage = p >= std::size_t(RenderPass::FluidSpheres);
            ImGui::Text(stage ? "  fluid %s" : "render %s", renderPassName(RenderPass(p)));
            ImGui::TableNextColumn();
            if (f.renderPassMs[p] >= 0.0)
                ImGui::Text("%.3f ms", f.renderPassMs[p]);
            else
                ImGui::TextUnformatted("-");
        }
        ImGui::EndTable();
    }
}

// Three short wrapped lines per body: the panel is narrow, and a table of six columns would not
// fit.
void bodies(const ViewerFigures& f) {
    ImGui::TextWrapped("Ctrl + left drag pulls a body (while running)");
    for (std::size_t b = 0; b < f.bodies.size(); ++b) {
        const BodyRow& row = f.bodies[b];
        const bool held = f.heldBody && *f.heldBody == b;
        ImGui::Separator();
        ImGui::TextWrapped("%zu: %s (collider %u)%s", b, row.asset.c_str(), row.collider,
                           held ? ", held" : "");
        ImGui::TextWrapped("%.3g kg, %.2f m/s, %s", row.mass, row.speed,
                           row.touching ? "in contact" : "no contact");
        ImGui::TextWrapped("submerged (by buoyancy) %.0f %%", 100.0 * row.submerged);
    }
}

void simulationParameters(ViewerUi& ui, ViewerActions& actions) {
    format::SimulationParams& p = ui.params;
    int minIterations = int(p.minIterations);
    int maxIterations = int(p.maxIterations);
    if (ImGui::SliderInt("min iterations", &minIterations, 1, 20)) {
        p.minIterations = std::uint32_t(minIterations);
        p.maxIterations = std::max(p.maxIterations, p.minIterations);
    }
    actions.applyParameters |= edited();
    if (ImGui::SliderInt("max iterations", &maxIterations, 1, 30)) {
        p.maxIterations = std::uint32_t(maxIterations);
        p.minIterations = std::min(p.minIterations, p.maxIterations);
    }
    actions.applyParameters |= edited();
    ImGui::SliderFloat("target error", &p.targetDensityError, 0.0f, 0.05f, "%.4f");
    actions.applyParameters |= edited();
    ImGui::SliderFloat("relaxation (eps)", &p.relaxation, 1e-4f, 1.0f, "%.4f",
                       ImGuiSliderFlags_Logarithmic);
    actions.applyParameters |= edited();
    ImGui::SliderFloat("s_corr k", &p.scorrK, 0.0f, 0.5f, "%.3f");
    actions.applyParameters |= edited();
    ImGui::SliderFloat("s_corr n", &p.scorrN, 1.0f, 8.0f, "%.1f");
    actions.applyParameters |= edited();
    ImGui::SliderFloat("s_corr dq [m]", &p.scorrDeltaQ, 0.0f, p.kernelRadius, "%.4f");
    actions.applyParameters |= edited();
    ImGui::SliderFloat("XSPH c", &p.xsph, 0.0f, 0.5f, "%.3f");
    actions.applyParameters |= edited();
    ImGui::SliderFloat("vorticity [m/s]", &p.vorticity, 0.0f, 0.05f, "%.4f");
    actions.applyParameters |= edited();
    ImGui::DragFloat3("gravity [m/s2]", &p.gravity.x, 0.05f, -50.0f, 50.0f, "%.2f");
    actions.applyParameters |= edited();
    float stepMs = p.timeStep * 1e3f;
    if (ImGui::SliderFloat("time step [ms]", &stepMs, 1.0f, 33.3f, "%.2f"))
        p.timeStep = stepMs * 1e-3f;
    actions.applyParameters |= edited();
    int substeps = int(p.substeps);
    if (ImGui::SliderInt("substeps", &substeps, 1, 16))
        p.substeps = std::uint32_t(substeps);
    actions.applyParameters |= edited();
}

void renderModes(ViewerUi& ui) {
    RenderSettings& r = ui.render;
    int surface = int(r.surface);
    ImGui::RadioButton("spheres", &surface, int(SurfaceMode::Spheres));
    ImGui::SameLine();
    ImGui::RadioButton("fluid surface", &surface, int(SurfaceMode::Fluid));
    ImGui::SameLine();
    ImGui::RadioButton("mesh", &surface, int(SurfaceMode::Mesh));
    r.surface = SurfaceMode(surface);
    if (r.surface == SurfaceMode::Mesh) {
        ImGui::Checkbox("anisotropic kernels", &r.mesh.anisotropic);
        ImGui::SameLine();
        bool normalised = isDensityNormalised(r.mesh);
        if (ImGui::Checkbox("density-normalised", &normalised))
            r.mesh.densityNormalised = normalised;
    }
    int colour = int(r.colour);
    ImGui::RadioButton("water", &colour, int(ColourMode::Water));
    ImGui::SameLine();
    ImGui::RadioButton("speed", &colour, int(ColourMode::Speed));
    ImGui::SameLine();
    ImGui::RadioButton("density error", &colour, int(ColourMode::DensityError));
    r.colour = ColourMode(colour);
    ImGui::SliderFloat("speed range [m/s]", &r.speedRange, 0.1f, 10.0f, "%.2f");
    ImGui::SliderFloat("error range", &r.densityErrorRange, 0.001f, 0.5f, "%.3f",
                       ImGuiSliderFlags_Logarithmic);
    ImGui::Checkbox("colliders", &r.drawColliders);
    ImGui::SameLine();
    ImGui::Checkbox("glass walls", &r.glassWalls);
    ImGui::SameLine();
    ImGui::Checkbox("floor", &r.drawFloor);
    ImGui::SameLine();
    ImGui::Checkbox("domain box", &r.drawDomainBox);
    if (r.surface == SurfaceMode::Fluid) {
        int iterations = int(r.smoothingIterations);
        ImGui::SliderInt("smoothing passes", &iterations, 0, 10);
        r.smoothingIterations = std::uint32_t(iterations);
        ImGui::SliderFloat("filter radius [r]", &r.filterRadius, 0.5f, 8.0f, "%.1f");
        ImGui::SliderFloat("absorption [1/m]", &r.absorption, 0.0f, 60.0f, "%.1f");
        ImGui::SliderFloat("refraction [px/m]", &r.refraction, 0.0f, 300.0f, "%.0f");
    }
}

} // namespace

const char* viewerKeyHelp() {
    return "Left drag       orbit\n"
           "Right/mid drag  pan (or Shift + left drag)\n"
           "Ctrl+left drag  pull a dynamic body (a spring; it acts while running)\n"
           "Wheel           zoom\n"
           "Space           pause / resume\n"
           "N, Right        one step (paused)\n"
           "R               reset the scene\n"
           "F               frame the scene\n"
           "C               next colour mode (water, speed, density error)\n"
           "M               spheres / fluid surface / surface mesh\n"
           "G               glass walls on / off\n"
           "P, F12          screenshot (PNG in the current folder)\n"
           "O               screenshots with / without the panel\n"
           "V               start / stop recording (MP4, needs ffmpeg)\n"
           "Tab             show / hide the panel\n"
           "F1, H           this help\n"
           "Esc, Q          quit";
}

PanelLayout panelLayout(float labelWidth, float fontSize, glm::vec2 display) {
    constexpr float kMargin = 10.0f;   // [pixels] from the window's edges
    constexpr float kSliderEms = 9.0f; // [font sizes] a slider's width when there is room
    constexpr float kChromeEms = 3.0f; // [font sizes] padding, label spacing, scroll bar
    constexpr float kMinSliderEms = 3.0f;
    PanelLayout layout;
    layout.position = {kMargin, kMargin};
    const float wanted = labelWidth + (kSliderEms + kChromeEms) * fontSize;
    layout.width = std::min(wanted, kPanelMaxWidthFraction * display.x);
    layout.maxHeight = std::max(display.y - 2.0f * kMargin, 4.0f * fontSize);
    layout.itemWidth =
        std::max(layout.width - labelWidth - kChromeEms * fontSize, kMinSliderEms * fontSize);
    return layout;
}

void drawViewerPanel(ViewerUi& ui, const ViewerFigures& figures, ViewerActions& actions) {
    const ImGuiIO& io = ImGui::GetIO();
    const PanelLayout layout = panelLayout(widestLabel(), ImGui::GetFontSize(),
                                           glm::vec2(io.DisplaySize.x, io.DisplaySize.y));
    ImGui::SetNextWindowPos(ImVec2(layout.position.x, layout.position.y), ImGuiCond_FirstUseEver);
    // Fixed width, following the window; as tall as the contents up to the window's height
    // (then it scrolls). The title bar's arrow collapses it, Tab hides it.
    ImGui::SetNextWindowSizeConstraints(ImVec2(layout.width, 0.0f),
                                        ImVec2(layout.width, layout.maxHeight));
    ImGui::SetNextWindowBgAlpha(0.8f);
    if (!ImGui::Begin("Sluice", &ui.showPanel, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::End();
        return;
    }
    ImGui::PushItemWidth(layout.itemWidth);
    if (ImGui::Button(ui.paused ? "Run" : "Pause"))
        ui.paused = !ui.paused;
    ImGui::SameLine();
    actions.step |= ImGui::Button("Step");
    ImGui::SameLine();
    actions.reset |= ImGui::Button("Reset");
    ImGui::SameLine();
    actions.reload |= ImGui::Button("Reload");
    ImGui::SameLine();
    actions.frame |= ImGui::Button("Frame");
    ImGui::SliderInt("steps per frame", &ui.stepsPerFrame, 1, 8);
    if (figures.hasEmitters && ImGui::Checkbox("emitters", &ui.emitters))
        actions.emitters = ui.emitters;

    // Bodies first: in a scene that has them they are what one watches.
    if (!figures.bodies.empty() &&
        ImGui::CollapsingHeader("Bodies", ImGuiTreeNodeFlags_DefaultOpen))
        bodies(figures);
    if (ImGui::CollapsingHeader("Statistics", ImGuiTreeNodeFlags_DefaultOpen))
        statistics(figures);
    if (ImGui::CollapsingHeader("Rendering", ImGuiTreeNodeFlags_DefaultOpen))
        renderModes(ui);
    if (ImGui::CollapsingHeader("Simulation", ImGuiTreeNodeFlags_DefaultOpen))
        simulationParameters(ui, actions);
    if (ImGui::CollapsingHeader("Capture")) {
        actions.screenshot |= ImGui::Button("Screenshot");
        ImGui::SameLine();
        actions.toggleRecording |= ImGui::Button(ui.recording ? "Stop recording" : "Record");
        ImGui::Checkbox("panel in screenshots", &ui.screenshotPanel);
    }
    if (!ui.status.empty())
        ImGui::TextWrapped("%s", ui.status.c_str());
    ImGui::PopItemWidth();
    ImGui::End();
}

void drawDragMarker(const BodyGrab& grab, const std::vector<BodyState>& bodies,
                    const OrbitCamera& camera, glm::uvec2 window) {
    if (window.x == 0 || window.y == 0)
        return;
    const ImU32 colour = IM_COL32(255, 200, 40, 230);
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    // project() gives a depth outside [0, 1] for points behind the eye or past the far plane.
    const glm::vec3 target = camera.project(grab.target, window);
    if (target.z < 0.0f || target.z > 1.0f)
        return;
    const ImVec2 to(target.x, target.y);
    draw->AddCircle(to, 6.0f, colour, 16, 2.0f);
    if (grab.body >= bodies.size())
        return;
    const glm::vec3 anchor = camera.project(bodies[grab.body].pose.toWorld(grab.anchor), window);
    if (anchor.z < 0.0f || anchor.z > 1.0f)
        return;
    const ImVec2 from(anchor.x, anchor.y);
    draw->AddLine(from, to, colour, 2.0f);
    draw->AddCircleFilled(from, 3.0f, colour);
}

void drawViewerHelp(bool& open) {
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f),
                            ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowBgAlpha(0.85f);
    if (ImGui::Begin("Keys", &open,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse))
        ImGui::TextUnformatted(viewerKeyHelp());
    ImGui::End();
}

} // namespace sluice::rt
