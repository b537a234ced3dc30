// The statistics sluice-play prints and writes: a fixed-width table and a JSON document.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

/// The median of `values` (the mean of the middle two for an even count); 0 when empty.
double median(std::vector<double> values);

/// Header lines of the statistics table.
std::string statsTableHeader();

/// One row of the table; gpuMs < 0 prints "-".
std::string statsTableRow(const StepStats& stats, double gpuMs);

/// A step's statistics as JSON (physics only: no timings, so deterministic runs compare equal).
nlohmann::json statsJson(const StepStats& stats);

/// Every dynamic body's state as JSON (docs/bodies.md, "Outputs"): an array of objects with
/// collider, mass, origin (the asset frame's origin in the world), centreOfMass, orientation
/// [x, y, z, w], linearVelocity, angularVelocity, force, torque, submergedShare and contacts.
/// The names are those of bodyTransformsJson and of the --bodies-csv columns.
nlohmann::json bodiesJson(const std::vector<BodyState>& bodies);

/// The body-transforms file written beside each PLY frame: for every body, its collider index
/// and asset, and the asset frame's world transform as origin, orientation quaternion
/// [x, y, z, w], uniform scale and a row-major 4x4 matrix (what Blender and Houdini import),
/// with the centre of mass beside it.
nlohmann::json bodyTransformsJson(const format::Scene& scene, std::uint64_t step, double time,
                                  const std::vector<BodyState>& bodies);

/// Per-pass GPU times as JSON {"predict": ms, ...}; passes without a figure are left out.
nlohmann::json passTimesJson(const PassTimes& times);

/// The derived constants and resolved parameters of a run, as JSON.
nlohmann::json parametersJson(const format::SimulationParams& params, const PbfConstants& k);

} // namespace sluice::rt
