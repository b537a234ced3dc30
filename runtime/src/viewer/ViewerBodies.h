// What the viewer panel's "Bodies" section shows of each dynamic body, with the submerged share
// smoothed over time for reading.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sluice/format/scene/Scene.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

/// One body's line in the panel.
struct BodyRow {
    std::uint32_t collider = 0; ///< index in the scene's colliders
    std::string asset;          ///< the collider's asset file name, without its folder
    double mass = 0.0;          ///< [kg]
    double speed = 0.0;         ///< of the centre of mass [m/s]
    /// BodyState::submergedShare averaged exponentially over kSmoothingTime of simulated time:
    /// the share of the body's volume under water that the fluid's buoyancy implies.
    double submerged = 0.0;
    bool touching = false; ///< it has contacts with a wall, collider or body
};

/// Turns Simulation::bodies() into the panel's rows, frame after frame.
class BodyReadout {
public:
    /// Time constant of the submerged share's average [s of simulated time].
    static constexpr double kSmoothingTime = 0.5;

    /// Takes the bodies after the latest step at simulated time `time` [s]. The average starts
    /// again when the bodies change in number or the clock goes back (reset, reload); a repeated
    /// `time` (paused) leaves it as it is.
    void update(const format::Scene& scene, const std::vector<BodyState>& bodies, double time);

    /// One row per body, in the order of Simulation::bodies(); empty before the first update.
    const std::vector<BodyRow>& rows() const { return m_rows; }

private:
    std::vector<BodyRow> m_rows;
    double m_time = 0.0; ///< simulated time of the last update [s]
};

} // namespace sluice::rt
