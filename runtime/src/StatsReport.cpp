// Formatting of step statistics for people (table) and programs (JSON).
#include "StatsReport.h"

#include <cstdio>

namespace sluice::rt {

std::string statsTableHeader() {
    return "   step   time [s]  particles  avg err %  max err %  max |v| [m/s]  inside  "
           "non-finite  iters  mask ovf  GPU ms/step\n"
           "-------  ---------  ---------  ---------  ---------  -------------  ------  "
           "----------  -----  --------  -----------\n";
}

std::string statsTableRow(const StepStats& s, double gpuMs) {
    char gpu[32] = "-";
    if (gpuMs >= 0.0)
        std::snprintf(gpu, sizeof gpu, "%.3f", gpuMs);
    char line[256];
    std::snprintf(line, sizeof line, "%7llu  %9.4f  %9u  %9.3f  %9.3f  %13.3f  %6u  %10u  %5u  %8u  %11s\n",
                  static_cast<unsigned long long>(s.step), s.time, s.particles,
                  100.0 * s.avgDensityError, 100.0 * s.maxDensityError, s.maxSpeed,
                  s.insideColliders, s.nonFinite, s.iterations, s.maskOverflow, gpu);
    return line;
}

nlohmann::json statsJson(const StepStats& s) {
    return {
        {"step", s.step},
        {"time", s.time},
        {"particles", s.particles},
        {"avgDensityError", s.avgDensityError},
        {"maxDensityError", s.maxDensityError},
        {"maxSpeed", s.maxSpeed},
        {"insideColliders", s.insideColliders},
        {"nonFinite", s.nonFinite},
        {"iterations", s.iterations},
        {"meanIterations", s.meanIterations},
        {"maskOverflow", s.maskOverflow},
        {"maxCandidates", s.maxCandidates},
        {"maxNeighbours", s.maxNeighbours},
        {"capacityReached", s.capacityReached},
    };
}

nlohmann::json passTimesJson(const PassTimes& times) {
    nlohmann::json out = nlohmann::json::object();
    for (std::size_t p = 0; p < times.size(); ++p)
        if (times[p] >= 0.0)
            out[passName(Pass(p))] = times[p];
    return out;
}

nlohmann::json parametersJson(const format::SimulationParams& p, const PbfConstants& k) {
    return {
        {"spacing", p.spacing},
        {"kernelRadius", p.kernelRadius},
        {"restDensity", p.restDensity},
        {"timeStep", p.timeStep},
        {"substeps", p.substeps},
        {"minIterations", p.minIterations},
        {"maxIterations", p.maxIterations},
        {"targetDensityError", p.targetDensityError},
        {"relaxation", p.relaxation},
        {"scorrK", p.scorrK},
        {"scorrN", p.scorrN},
        {"scorrDeltaQ", p.scorrDeltaQ},
        {"xsph", p.xsph},
        {"vorticity", p.vorticity},
        {"gravity", {p.gravity.x, p.gravity.y, p.gravity.z}},
        {"capacity", p.capacity},
        {"derived",
         {{"particleMass", k.mass},
          {"particleRadius", k.radius},
          {"epsilon", k.epsilon},
          {"substepDt", k.dt}}},
    };
}

} // namespace sluice::rt
