// The scene a viewer plays: its file, colliders, simulation and renderer, with the live changes
// the panel and the mouse make (parameters, emitters on or off, reset, reload from disk, a body
// pulled by the mouse spring).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "viewer/ViewerPick.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/rt/sim/Simulation.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {

/// One scene, live. Needs the current GL context for its whole life.
class ViewerSession {
public:
    /// Reads the scene and its colliders, creates the simulation and a renderer of `size`.
    static Result<ViewerSession> open(const std::string& scenePath, bool deterministic,
                                      glm::uvec2 size);

    /// One simulation step (queues GPU work only).
    void step();

    /// Puts the (edited) scene back at its initial state; a grabbed body is let go.
    Result<void> reset();
    /// Reads the scene file and its colliders again; edits are dropped and a grabbed body is
    /// let go. On failure the session is unchanged and the error says why.
    Result<void> reload();

    /// Runs on with `params` from the next step (Simulation::setParameters: the particles, the
    /// clock and the emitter schedules carry on; spacing, rest density and capacity stay).
    /// InvalidArgument or NonFinite, with nothing changed, for values the solver refuses.
    Result<void> applyParameters(const format::SimulationParams& params);
    /// Turns the scene's emitters on or off from now on; reset keeps the choice.
    void setEmittersEnabled(bool on);

    /// Grabs the dynamic body `ray` meets first (Simulation::pickBody, a sync) with the mouse
    /// spring, its target at the hit point; the spring acts from the next step. nullopt, with
    /// nothing grabbed, when the ray meets no body.
    std::optional<BodyHit> grabBody(const Ray& ray);
    /// Moves the grabbed point's target to `ray` at the grab distance (the cursor moved or the
    /// camera did). Nothing happens without a grab.
    void dragBody(const Ray& ray);
    /// Lets go of the grabbed body (nothing happens without a grab).
    void releaseBody();
    /// The body held by the mouse spring, if any.
    const std::optional<BodyGrab>& grab() const { return m_grab; }
    /// The scene has dynamic colliders.
    bool hasBodies() const;

    Simulation& simulation() { return *m_sim; }
    const Simulation& simulation() const { return *m_sim; }
    Renderer& renderer() { return *m_renderer; }
    const Renderer& renderer() const { return *m_renderer; }
    /// The scene as edited (parameters), as read from the file otherwise.
    const format::Scene& scene() const { return m_scene; }
    bool emittersEnabled() const { return m_emittersOn; }
    /// Simulated time [s] and steps since the scene (re)started.
    double time() const { return m_sim->time(); }
    std::uint64_t steps() const { return m_sim->steps(); }

private:
    ViewerSession() = default;

    format::Scene m_scene;
    std::vector<format::ColliderAsset> m_colliders;
    bool m_deterministic = false;
    bool m_emittersOn = true;
    std::optional<Simulation> m_sim;
    std::optional<Renderer> m_renderer;
    std::optional<BodyGrab> m_grab;
};

} // namespace sluice::rt
