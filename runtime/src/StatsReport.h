// The statistics sluice-play prints and writes: a fixed-width table and a JSON document.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sluice/rt/Simulation.h"

namespace sluice::rt {

/// Header lines of the statistics table.
std::string statsTableHeader();

/// One row of the table; gpuMs < 0 prints "-".
std::string statsTableRow(const StepStats& stats, double gpuMs);

/// A step's statistics as JSON (physics only: no timings, so deterministic runs compare equal).
nlohmann::json statsJson(const StepStats& stats);

/// Per-pass GPU times as JSON {"predict": ms, ...}; passes without a figure are left out.
nlohmann::json passTimesJson(const PassTimes& times);

/// The derived constants and resolved parameters of a run, as JSON.
nlohmann::json parametersJson(const format::SimulationParams& params, const PbfConstants& k);

} // namespace sluice::rt
