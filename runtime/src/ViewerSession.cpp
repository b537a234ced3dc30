// Live scene changes for the viewer: parameters and emitters through the simulation's setters,
// reset and reload by building it again.
#include "ViewerSession.h"

#include "sluice/format/SceneIO.h"

namespace sluice::rt {

Result<ViewerSession> ViewerSession::open(const std::string& scenePath, bool deterministic,
                                          glm::uvec2 size) {
    auto scene = format::readScene(scenePath);
    if (!scene)
        return scene.error();
    auto colliders = loadSceneColliders(*scene);
    if (!colliders)
        return colliders.error();
    SimulationOptions options;
    options.deterministic = deterministic;
    auto sim = Simulation::create(*scene, *colliders, options);
    if (!sim)
        return sim.error();
    auto renderer = Renderer::create(*scene, *colliders, size);
    if (!renderer)
        return renderer.error();
    ViewerSession session;
    session.m_scene = std::move(*scene);
    session.m_colliders = std::move(*colliders);
    session.m_deterministic = deterministic;
    session.m_sim.emplace(std::move(*sim));
    session.m_renderer.emplace(std::move(*renderer));
    return session;
}

void ViewerSession::step() {
    m_sim->step();
}

Result<void> ViewerSession::reset() {
    SimulationOptions options;
    options.deterministic = m_deterministic;
    auto sim = Simulation::create(m_scene, m_colliders, options);
    if (!sim)
        return sim.error();
    sim->setEmittersEnabled(m_emittersOn);
    m_sim.emplace(std::move(*sim));
    return {};
}

Result<void> ViewerSession::reload() {
    auto fresh = open(m_scene.path, m_deterministic, m_renderer->size());
    if (!fresh)
        return fresh.error();
    // The old simulation and renderer go first (they share the context with the new ones).
    m_sim.reset();
    m_renderer.reset();
    *this = std::move(*fresh);
    return {};
}

Result<void> ViewerSession::applyParameters(const format::SimulationParams& params) {
    if (auto ok = m_sim->setParameters(params); !ok)
        return ok;
    m_scene.simulation = m_sim->parameters();
    return {};
}

void ViewerSession::setEmittersEnabled(bool on) {
    m_emittersOn = on;
    m_sim->setEmittersEnabled(on);
}

} // namespace sluice::rt
