// Formatting of step statistics for people (table) and programs (JSON).
#include "output/StatsReport.h"

#include <algorithm>
#include <cstdio>

#include <glm/gtc/quaternion.hpp>

#include "sluice/format/scene/SimulationLimits.h"

namespace sluice::rt {

double median(std::vector<double> values) {
    if (values.empty())
        return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

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
    std::snprintf(line, sizeof line,
                  "%7llu  %9.4f  %9u  %9.3f  %9.3f  %13.3f  %6u  %10u  %5u  %8u  %11s\n",
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
        {"bodyFaults", s.bodyFaults},
    };
}

namespace {

nlohmann::json vec3Json(glm::vec3 v) {
    return {v.x, v.y, v.z};
}
nlohmann::json quatJson(glm::quat q) {
    return {q.x, q.y, q.z, q.w};
}

} // namespace

nlohmann::json bodiesJson(const std::vector<BodyState>& bodies) {
    nlohmann::json out = nlohmann::json::array();
    for (const BodyState& b : bodies)
        out.push_back({
            {"collider", b.collider},
            {"mass", b.mass},
            {"origin", vec3Json(b.pose.translation)},
            {"centreOfMass", vec3Json(b.position)},
            {"orientation", quatJson(b.orientation)},
            {"linearVelocity", vec3Json(b.linearVelocity)},
            {"angularVelocity", vec3Json(b.angularVelocity)},
            {"force", vec3Json(b.force)},
            {"torque", vec3Json(b.torque)},
            {"submergedShare", b.submergedShare},
            {"contacts", b.contacts},
            {"kinematic", b.kinematic},
        });
    return out;
}

nlohmann::json bodyTransformsJson(const format::Scene& scene, std::uint64_t step, double time,
                                  const std::vector<BodyState>& bodies) {
    nlohmann::json list = nlohmann::json::array();
    for (const BodyState& b : bodies) {
        const ColliderPose& pose = b.pose;
        const glm::mat3 r = glm::mat3_cast(pose.rotation) * pose.scale;
        nlohmann::json matrix = nlohmann::json::array();
        for (int row = 0; row < 3; ++row)
            matrix.push_back({r[0][row], r[1][row], r[2][row], pose.translation[row]});
        matrix.push_back({0.0f, 0.0f, 0.0f, 1.0f});
        list.push_back({
            {"collider", b.collider},
            {"asset", format::colliderName(scene.colliders[b.collider])},
            {"origin", vec3Json(pose.translation)},
            {"centreOfMass", vec3Json(b.position)},
            {"orientation", quatJson(pose.rotation)},
            {"scale", pose.scale},
            {"matrix", matrix},
        });
    }
    return {{"step", step}, {"time", time}, {"bodies", list}};
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
          {"substepDt", k.dt},
          {"bodySurfaceOffset", k.bodyOffset}}},
    };
}

} // namespace sluice::rt
