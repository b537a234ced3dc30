// The phase timeline of a bake for people and for JSON (`sluice-bake bake --profile`).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "sluice/bake/jobs/PhaseLog.h"

namespace sluice::bake::cli {

/// {"totalSeconds", "phasesSeconds", "unaccountedSeconds", "cpuSeconds", "phases": [{"name",
/// "wallSeconds", "cpuSeconds"}...], "overlapped": [...]}: the total is the process's age at the
/// last lap, the unaccounted remainder the total minus the phases' sum.
nlohmann::ordered_json phasesJson(const PhaseLog& log);

/// The same as an indented table, one phase a line, with the total and the remainder.
std::string describePhases(const PhaseLog& log);

} // namespace sluice::bake::cli
