// Live scene changes for the viewer: parameters, emitters and the mouse spring through the
// simulation's setters, reset and reload by building it again.
#include "viewer/ViewerSession.h"

#include <algorithm>
#include <iostream>

#include "play/RunProgress.h"

#include "sluice/format/support/Assert.h"
#include "sluice/format/scene/SceneIO.h"

namespace sluice::rt {

Result<ViewerSession> ViewerSession::open(const std::string& scenePath, bool deterministic,
                                          glm::uvec2 size) {
    auto scene = format::readScene(scenePath);
    if (!scene)
        return scene.error();
    auto colliders = loadSceneColliders(*scene);
    if (!colliders)
        return colliders.error();
    if (auto warning = slowLoadWarning(*scene, *colliders))
        std::cerr << "sluice-play: warning [slow-load]: " << *warning << std::endl;
    SimulationOptions options;
    options.deterministic = deterministic;
    options.timers = true; // the panel's profiler
    auto sim = Simulation::create(*scene, *colliders, options);
    if (!sim)
        return sim.error();
    if (auto note = volumeMapNote(*scene, sim->volumeMapLoad()))
        std::cerr << "sluice-play: " << *note << std::endl;
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
    options.timers = true;
    auto sim = Simulation::create(m_scene, m_colliders, options);
    if (!sim)
        return sim.error();
    sim->setEmittersEnabled(m_emittersOn);
    m_sim.emplace(std::move(*sim)); // a fresh simulation holds no drag
    m_grab.reset();
    return {};
}

Result<void> ViewerSession::reload() {
    auto fresh = open(m_scene.path, m_deterministic, m_renderer->size());
    if (!fresh)
        return fresh.error();
    // The old simulation and renderer go first (they share the context with the new ones).
    m_sim.reset();
    m_renderer.reset();
    *this = std::move(*fresh); // the fresh session holds no grab
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

std::optional<BodyHit> ViewerSession::grabBody(const Ray& ray) {
    releaseBody();
    const std::optional<BodyHit> hit = m_sim->pickBody(ray.origin, ray.direction);
    if (!hit)
        return std::nullopt;
    m_grab = BodyGrab{hit->body, hit->anchor, hit->distance, hit->point};
    // The target starts where the anchor is, so the grab itself does not pull.
    const auto ok = m_sim->setDrag(BodyDrag{hit->body, hit->anchor, hit->point});
    SLUICE_ASSERT(ok, "ViewerSession::grabBody: the picked body was refused");
    return hit;
}

void ViewerSession::dragBody(const Ray& ray) {
    if (!m_grab)
        return;
    const glm::vec3 target = ray.at(m_grab->distance);
    // A degenerate ray (a camera state that gives non-finite numbers) keeps the last target.
    if (!m_sim->setDrag(BodyDrag{m_grab->body, m_grab->anchor, target}))
        return;
    m_grab->target = target;
}

void ViewerSession::releaseBody() {
    if (!m_grab)
        return;
    m_grab.reset();
    (void)m_sim->setDrag(std::nullopt); // letting go cannot fail
}

bool ViewerSession::hasBodies() const {
    return std::any_of(m_scene.colliders.begin(), m_scene.colliders.end(),
                       [](const format::SceneCollider& c) { return c.dynamic.has_value(); });
}

} // namespace sluice::rt
