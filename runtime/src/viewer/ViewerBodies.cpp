// The panel's body rows: plain figures copied from the simulation, the noisy submerged share
// averaged over simulated time.
#include "viewer/ViewerBodies.h"

#include <cmath>
#include <filesystem>

#include <glm/geometric.hpp>

namespace sluice::rt {

void BodyReadout::update(const format::Scene& scene, const std::vector<BodyState>& bodies,
                         double time) {
    const bool restart = bodies.size() != m_rows.size() || time < m_time;
    // The share comes from one step's fluid force, so it jitters from step to step: an
    // exponential average over simulated time reads steadily at any frame or step rate.
    const double weight = restart ? 1.0 : 1.0 - std::exp(-(time - m_time) / kSmoothingTime);
    m_rows.resize(bodies.size());
    for (std::size_t b = 0; b < bodies.size(); ++b) {
        const BodyState& state = bodies[b];
        BodyRow& row = m_rows[b];
        const std::string asset =
            state.collider < scene.colliders.size()
                ? std::filesystem::path(format::colliderName(scene.colliders[state.collider]))
                      .filename()
                      .string()
                : std::string();
        if (restart || row.collider != state.collider || row.asset != asset) {
            row.collider = state.collider;
            row.asset = asset;
            row.submerged = state.submergedShare;
        } else {
            row.submerged += weight * (state.submergedShare - row.submerged);
        }
        row.mass = state.mass;
        row.speed = glm::length(state.linearVelocity);
        row.touching = state.contacts > 0;
    }
    m_time = time;
}

} // namespace sluice::rt
