// --bodies-csv: every dynamic body's trajectory in one table, one row per recorded step and
// body, for spreadsheets, pandas and Houdini's table import.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sluice/format/scene/Scene.h"
#include "sluice/format/support/Result.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

/// The columns, in order (docs/bodies.md, "Outputs"): step, time [s], body (index into the
/// bodies), collider (index into the scene's colliders), asset, origin_x/y/z (the asset
/// frame's origin in the world [m]), centre_of_mass_x/y/z [m], orientation_x/y/z/w (asset frame
/// to world), linear_velocity_x/y/z [m/s], angular_velocity_x/y/z [rad/s], submerged_share,
/// force_x/y/z (the fluid's force on the body, mean over the step [N]). The JSON outputs use
/// the same names in camelCase.
std::string bodiesCsvHeader();

/// The rows of one recorded step: one per body, each ending in '\n'. Numbers are printed with
/// 9 significant digits (a float round-trips), so deterministic runs give identical files.
std::string bodiesCsvRows(const format::Scene& scene, std::uint64_t step, double time,
                          const std::vector<BodyState>& bodies);

/// Collects rows over a run and writes them in one go, atomically (a reader never sees half a
/// file; an interrupted run writes the steps it recorded).
class BodiesCsv {
public:
    explicit BodiesCsv(std::string path) : m_path(std::move(path)) {}

    bool enabled() const { return !m_path.empty(); }
    void record(const format::Scene& scene, std::uint64_t step, double time,
                const std::vector<BodyState>& bodies);
    Result<void> write() const;

private:
    std::string m_path; ///< empty: not asked for
    std::string m_rows;
};

} // namespace sluice::rt
