// The simulation parameters' ranges (SimulationLimits.h): one table, one check.
#include "sluice/format/scene/SimulationLimits.h"

#include <cmath>
#include <limits>

#include "sluice/format/support/Assert.h"
#include "support/Json.h"

namespace sluice::format {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

ParamRange closed(double lo, double hi, std::string note = {}) {
    return {lo, hi, false, false, std::move(note)};
}
ParamRange atLeast(double lo) {
    return {lo, kInf, false, false, {}};
}
ParamRange above(double lo) {
    return {lo, kInf, true, false, {}};
}

constexpr std::string_view kFloatParams[] = {
    "spacing", "kernelRadius", "restDensity", "timeStep", "targetDensityError", "relaxation",
    "scorrK",  "scorrN",       "scorrDeltaQ", "xsph",     "vorticity"};

// The member of `p` named `name` (a float parameter).
float floatParam(const SimulationParams& p, std::string_view name) {
    const std::pair<std::string_view, float SimulationParams::*> fields[] = {
        {"spacing", &SimulationParams::spacing},
        {"kernelRadius", &SimulationParams::kernelRadius},
        {"restDensity", &SimulationParams::restDensity},
        {"timeStep", &SimulationParams::timeStep},
        {"targetDensityError", &SimulationParams::targetDensityError},
        {"relaxation", &SimulationParams::relaxation},
        {"scorrK", &SimulationParams::scorrK},
        {"scorrN", &SimulationParams::scorrN},
        {"scorrDeltaQ", &SimulationParams::scorrDeltaQ},
        {"xsph", &SimulationParams::xsph},
        {"vorticity", &SimulationParams::vorticity}};
    for (const auto& [field, member] : fields)
        if (field == name)
            return p.*member;
    SLUICE_ASSERT(false, "floatParam: not a float simulation parameter");
    return 0.0f;
}

} // namespace

ParamRange simulationParamRange(std::string_view name, float spacing, float kernelRadius) {
    // Below 1.5 spacings the rest lattice's nearest neighbours sit at or past h, where the
    // spiky gradient vanishes: the lambda denominator is 0 and the solver constants infinite
    // (found by tests/fuzz at h = s).
    // Bounds are computed in float, as the values are stored, then compared exactly in double.
    if (name == "spacing")
        return closed(double(1e-4f), 10.0);
    if (name == "kernelRadius")
        return closed(double(1.5f * spacing), double(4.0f * spacing),
                      "1.5 to 4 times spacing " + detail::formatFloat(spacing));
    if (name == "restDensity")
        return above(0.0);
    if (name == "timeStep")
        return {0.0, 1.0, true, false, {}};
    if (name == "targetDensityError")
        return closed(0.0, 1.0);
    if (name == "relaxation")
        return closed(0.0, 100.0);
    if (name == "scorrK" || name == "vorticity")
        return atLeast(0.0);
    if (name == "scorrN")
        return closed(1.0, 8.0);
    if (name == "scorrDeltaQ")
        return {0.0, double(kernelRadius), false, true,
                "0 to kernelRadius " + detail::formatFloat(kernelRadius) + ", excluded"};
    if (name == "xsph")
        return closed(0.0, 1.0);
    if (name == "substeps" || name == "minIterations" || name == "maxIterations")
        return closed(1.0, 1000.0);
    if (name == "capacity")
        return closed(1.0, double(kMaxSceneParticles));
    SLUICE_ASSERT(false, "simulationParamRange: not a simulation parameter");
    return {};
}

std::string rangeProblem(double value, const std::string& shown, const ParamRange& b) {
    const bool low = b.loOpen ? !(value > b.lo) : !(value >= b.lo);
    const bool high = b.hiOpen ? !(value < b.hi) : !(value <= b.hi);
    if (!low && !high)
        return {};
    std::string problem = shown + " is out of range";
    if (std::isinf(b.hi))
        problem += std::string(": must be ") + (b.loOpen ? "> " : ">= ") +
                   detail::formatFloat(float(b.lo));
    else
        problem += std::string(" ") + (b.loOpen ? "(" : "[") + detail::formatFloat(float(b.lo)) +
                   ", " + detail::formatFloat(float(b.hi)) + (b.hiOpen ? ")" : "]");
    if (!b.note.empty())
        problem += " (" + b.note + ")";
    return problem;
}

BoundaryModelName boundaryModelNamed(std::string_view name) {
    if (name == "solids")
        return BoundaryModelName::Solids;
    if (name == "bodies")
        return BoundaryModelName::Removed;
    return BoundaryModelName::Unknown;
}

std::string unknownBoundaryModel(std::string_view name) {
    return "unknown boundary model \"" + detail::displayKey(std::string(name)) +
           "\"; there is one, \"solids\" (the walls, colliders and bodies add boundary volume), "
           "the default: leave the key out";
}

std::string removedBoundaryModelWarning() {
    return "simulation.boundary: \"bodies\" was removed; the walls, colliders and bodies all add "
           "boundary volume now (\"solids\", the only model: docs/pbf.md, \"Boundary volume\"), "
           "so this scene plays with it; remove the key to silence this";
}

Result<void> checkSimulationParams(const SimulationParams& p) {
    for (const std::string_view name : kFloatParams) {
        const float v = floatParam(p, name);
        if (!std::isfinite(v))
            return fail(ErrorCode::NonFinite, std::string(name) + " is not finite");
        const std::string problem = rangeProblem(
            v, detail::formatFloat(v), simulationParamRange(name, p.spacing, p.kernelRadius));
        if (!problem.empty())
            return fail(ErrorCode::InvalidArgument, std::string(name) + ": " + problem);
    }
    if (!std::isfinite(p.gravity.x) || !std::isfinite(p.gravity.y) || !std::isfinite(p.gravity.z))
        return fail(ErrorCode::NonFinite, "gravity is not finite");
    const std::pair<std::string_view, std::uint32_t> counts[] = {{"substeps", p.substeps},
                                                                 {"minIterations", p.minIterations},
                                                                 {"maxIterations", p.maxIterations},
                                                                 {"capacity", p.capacity}};
    for (const auto& [name, v] : counts) {
        const std::string problem = rangeProblem(
            double(v), std::to_string(v), simulationParamRange(name, p.spacing, p.kernelRadius));
        if (!problem.empty())
            return fail(ErrorCode::InvalidArgument, std::string(name) + ": " + problem);
    }
    if (p.maxIterations < p.minIterations)
        return fail(ErrorCode::InvalidArgument, "maxIterations " + std::to_string(p.maxIterations) +
                                                    " is less than minIterations " +
                                                    std::to_string(p.minIterations));
    return {};
}

} // namespace sluice::format
