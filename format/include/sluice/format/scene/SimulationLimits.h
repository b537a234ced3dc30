// The ranges of the simulation parameters, defined once: the scene reader, the solver's
// setParameters (so the viewer's panel and Python's set_parameters) all check against them.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "sluice/format/support/Result.h"
#include "sluice/format/scene/Scene.h"

namespace sluice::format {

/// Where a parameter may lie: lo .. hi, each end open (excluded) or closed; `note` says it in
/// the scene's terms where the bounds follow from other parameters ("1.5 to 4 times spacing").
struct ParamRange {
    double lo = 0.0;
    double hi = 0.0; ///< +infinity: no upper bound
    bool loOpen = false;
    bool hiOpen = false;
    std::string note;
};

/// The range of the float parameter `name` of SimulationParams ("xsph", "kernelRadius", ...) at
/// particle spacing `spacing` and kernel radius `kernelRadius` [m]; the integer ones
/// ("substeps", "minIterations", "maxIterations", "capacity") too. Asserts on another name.
ParamRange simulationParamRange(std::string_view name, float spacing, float kernelRadius);

/// Empty when `value` lies in `range`, else what is wrong with it, as the scene reader says it:
/// "1.5 is out of range [0, 1]" or "-2 is out of range: must be > 0", with the note after it.
/// `shown` is the value as the user wrote it.
std::string rangeProblem(double value, const std::string& shown, const ParamRange& range);

/// Every parameter of `p` in its range (the gravity finite, maxIterations at least
/// minIterations): NonFinite for a value that is not finite, InvalidArgument naming the
/// parameter and its range for one out of range ("xsph: 5 is out of range [0, 1]").
Result<void> checkSimulationParams(const SimulationParams& p);

/// What a "simulation.boundary" value names (docs/scene-format.md): the one boundary model
/// there is ("solids", the walls and every collider and body adding boundary volume), the one
/// removed on 2026-12-08 ("bodies", only dynamic bodies adding it), or neither.
enum class BoundaryModelName { Solids, Removed, Unknown };
BoundaryModelName boundaryModelNamed(std::string_view name);

/// What an unknown model name is told: `unknown boundary model "NAME"; ...`, the name shown
/// escaped and cut short as the scene reader shows keys.
std::string unknownBoundaryModel(std::string_view name);

/// What a scene naming the removed model ("bodies") is told: it plays with the one model.
std::string removedBoundaryModelWarning();

} // namespace sluice::format
