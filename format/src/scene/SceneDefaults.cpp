// The scene's derived defaults and the check of a whole Scene value (SceneDefaults.h): what the
// reader does key by key for a file, done once for a scene built in code.
#include "sluice/format/scene/SceneDefaults.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "scene/SceneReading.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/format/scene/SimulationLimits.h"
#include "sluice/format/scene/SolverReach.h"
#include "support/Json.h"

namespace sluice::format {
namespace {

using detail::formatFloat;
using detail::formatNumber;
using scene_detail::vecText; // as the reader writes vectors in its messages

constexpr std::uint32_t kMaxDefaultSubsteps = 64;
constexpr double kCflNumber = 0.4; // a particle moves at most 0.4 h per substep
constexpr double kInf = std::numeric_limits<double>::infinity();

bool finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The first problem found, with the field's path: "colliders[2].scale: -1 is out of range".
class SceneCheck {
public:
    explicit SceneCheck(const Scene& scene) : m_label(scene.path.empty() ? "scene" : scene.path) {}

    bool ok() const { return !m_error; }
    Error error() const { return *m_error; }

    void vec(const std::string& path, glm::vec3 v) {
        if (ok() && !finite(v))
            fail(ErrorCode::NonFinite, path, vecText(v) + " is not finite");
    }
    void number(const std::string& path, float v, const ParamRange& range) {
        if (!ok())
            return;
        if (!std::isfinite(v))
            return fail(ErrorCode::NonFinite, path, formatFloat(v) + " is not finite");
        std::string problem = rangeProblem(v, formatFloat(v), range);
        if (!problem.empty())
            fail(ErrorCode::InvalidArgument, path, std::move(problem));
    }
    void fail(ErrorCode code, const std::string& path, std::string problem) {
        if (ok())
            m_error = Error{code, m_label + ": " + path + ": " + std::move(problem)};
    }

private:
    std::string m_label;
    std::optional<Error> m_error;
};

ParamRange above(double lo) {
    return {lo, kInf, true, false, {}};
}
ParamRange atLeast(double lo) {
    return {lo, kInf, false, false, {}};
}
ParamRange closed(double lo, double hi) {
    return {lo, hi, false, false, {}};
}

void checkBlock(SceneCheck& check, const FluidBlock& b, const std::string& path, float spacing) {
    if (b.shape == FluidBlock::Shape::Box) {
        check.vec(path + ".min", b.min);
        check.vec(path + ".max", b.max);
        for (int a = 0; a < 3 && check.ok(); ++a)
            if (!(b.max[a] > b.min[a]))
                check.fail(ErrorCode::InvalidArgument, path + ".max",
                           vecText(b.max) + " must exceed min " + vecText(b.min) +
                               " on every axis");
    } else {
        check.vec(path + ".center", b.center);
        check.number(path + ".radius", b.radius, above(0.0));
    }
    check.vec(path + ".velocity", b.velocity);
    if (!check.ok())
        return;
    const std::uint64_t n = blockParticleCount(b, spacing);
    if (n == 0)
        check.fail(ErrorCode::InvalidArgument, path,
                   "holds no particles at spacing " + formatFloat(spacing));
    else if (n > kMaxSceneParticles)
        check.fail(ErrorCode::SizeOverflow, path,
                   "holds more than " + std::to_string(kMaxSceneParticles) +
                       " particles (the limit) at spacing " + formatFloat(spacing));
}

void checkEmitter(SceneCheck& check, const Emitter& e, const std::string& path, float spacing) {
    check.vec(path + ".position", e.position);
    check.vec(path + ".direction", e.direction);
    if (check.ok() && !(glm::length(glm::dvec3(e.direction)) > 0.0))
        check.fail(ErrorCode::InvalidArgument, path + ".direction",
                   "has no direction (zero vector)");
    check.number(path + ".radius", e.radius,
                 {double(0.5f * spacing), kInf, false, false, "at least spacing / 2"});
    check.number(path + ".speed", e.speed, above(0.0));
    check.number(path + ".rate", e.rate, atLeast(0.0));
    check.number(path + ".start", e.start, atLeast(0.0));
    check.number(path + ".stop", e.stop, {double(e.start), kInf, true, false, "after start"});
    if (check.ok() && emitterDiscCount(e.radius, spacing) > kMaxSceneParticles)
        check.fail(ErrorCode::SizeOverflow, path + ".radius",
                   "a disc of radius " + formatFloat(e.radius) + " holds more than " +
                       std::to_string(kMaxSceneParticles) + " particles (the limit)");
}

void checkShape(SceneCheck& check, const ColliderShape& s, const std::string& path) {
    const std::string at = path + ".shape." + shapeName(s.kind);
    if (s.kind == ColliderShape::Kind::Box) {
        check.vec(at + ".size", s.size);
        if (check.ok() && !(s.size.x > 0.0f && s.size.y > 0.0f && s.size.z > 0.0f))
            check.fail(ErrorCode::InvalidArgument, at + ".size",
                       vecText(s.size) + " must be > 0 on every axis");
    } else {
        check.number(at + ".radius", s.radius, above(0.0));
    }
    if (s.kind == ColliderShape::Kind::Capsule)
        check.number(at + ".height", s.height,
                     {2.0 * double(s.radius), kInf, false, false, "at least 2 * radius"});
    check.number(at + ".voxel", s.voxelSize, above(0.0));
}

void checkCollider(SceneCheck& check, const SceneCollider& c, const std::string& path) {
    if (c.shape)
        checkShape(check, *c.shape, path);
    check.vec(path + ".translation", c.translation);
    check.vec(path + ".rotation", c.rotationDegrees);
    check.number(path + ".scale", c.scale, above(0.0));
    check.number(path + ".friction", c.friction, closed(0.0, 1.0));
    check.vec(path + ".motion.linearVelocity", c.linearVelocity);
    check.vec(path + ".motion.angularVelocity", c.angularVelocityDegrees);
    const bool moves = !c.keys.empty() || c.linearVelocity != glm::vec3(0.0f) ||
                       c.angularVelocityDegrees != glm::vec3(0.0f);
    if (check.ok() && !c.keys.empty() &&
        (c.linearVelocity != glm::vec3(0.0f) || c.angularVelocityDegrees != glm::vec3(0.0f)))
        check.fail(ErrorCode::InvalidArgument, path + ".motion",
                   "has both keyframes and velocities; a collider moves by one or the other");
    for (std::size_t k = 0; k < c.keys.size() && check.ok(); ++k) {
        const std::string key = path + ".motion.keyframes[" + std::to_string(k) + "]";
        check.number(key + ".time", c.keys[k].time, atLeast(-kInf));
        check.vec(key + ".translation", c.keys[k].translation);
        check.vec(key + ".rotation", c.keys[k].rotationDegrees);
        if (check.ok() && k > 0 && !(c.keys[k].time > c.keys[k - 1].time))
            check.fail(ErrorCode::InvalidArgument, key + ".time",
                       formatFloat(c.keys[k].time) + " is not after the previous key's time " +
                           formatFloat(c.keys[k - 1].time) + " (times must strictly increase)");
    }
    if (!c.dynamic || !check.ok())
        return;
    if (c.measureForce)
        return check.fail(ErrorCode::InvalidArgument, path + ".measureForce",
                          "not allowed on a dynamic body: its force is always reported");
    const DynamicBody& d = *c.dynamic;
    if (moves)
        return check.fail(ErrorCode::InvalidArgument, path + ".dynamic",
                          "a dynamic body has no motion (velocities and keys are the fluid's)");
    if (d.density.has_value() == d.mass.has_value())
        return check.fail(ErrorCode::InvalidArgument, path + ".dynamic",
                          "needs exactly one of density [kg/m^3] and mass [kg]");
    if (d.density)
        check.number(path + ".dynamic.density", *d.density, above(0.0));
    if (d.mass)
        check.number(path + ".dynamic.mass", *d.mass, above(0.0));
    check.vec(path + ".dynamic.linearVelocity", d.linearVelocity);
    check.vec(path + ".dynamic.angularVelocity", d.angularVelocityDegrees);
    check.number(path + ".dynamic.friction", d.friction, closed(0.0, 2.0));
    check.number(path + ".dynamic.restitution", d.restitution, closed(0.0, 1.0));
}

void checkDomain(SceneCheck& check, const Scene& scene) {
    if (scene.domainMin.has_value() != scene.domainMax.has_value())
        return check.fail(ErrorCode::InvalidArgument, "domain",
                          "needs both a min and a max corner, or neither");
    if (!scene.domainMin)
        return;
    check.vec("domain.min", *scene.domainMin);
    check.vec("domain.max", *scene.domainMax);
    const float s = scene.simulation.spacing;
    for (int a = 0; a < 3 && check.ok(); ++a)
        if (!((*scene.domainMax)[a] - (*scene.domainMin)[a] >= s))
            check.fail(ErrorCode::InvalidArgument, "domain.max",
                       std::string("the domain is ") +
                           formatFloat((*scene.domainMax)[a] - (*scene.domainMin)[a]) +
                           " wide on " + "xyz"[a] + ", less than one spacing " + formatFloat(s));
}

// The parameters that the blocks' and emitters' checks and the derived defaults depend on,
// checked before those use them.
Result<void> checkLattice(const Scene& scene) {
    const SimulationParams& p = scene.simulation;
    SceneCheck check(scene);
    check.number("simulation.spacing", p.spacing, simulationParamRange("spacing", 1.0f, 1.0f));
    check.number("simulation.timeStep", p.timeStep, simulationParamRange("timeStep", 1.0f, 1.0f));
    check.vec("simulation.gravity", p.gravity);
    if (!check.ok())
        return check.error();
    return {};
}

} // namespace

Result<void> checkDrains(const std::vector<Drain>& drains, const std::string& what) {
    if (drains.size() > kMaxDrains)
        return fail(ErrorCode::InvalidArgument, std::to_string(drains.size()) + " " + what +
                                                    ", more than the limit " +
                                                    std::to_string(kMaxDrains));
    for (std::size_t i = 0; i < drains.size(); ++i) {
        const std::string at = "[" + std::to_string(i) + "]";
        if (!finite(drains[i].min) || !finite(drains[i].max))
            return fail(ErrorCode::NonFinite, at + ".box: a corner is not finite");
        for (int a = 0; a < 3; ++a)
            if (!(drains[i].max[a] > drains[i].min[a]))
                return fail(ErrorCode::InvalidArgument,
                            at + ".box.max: " + vecText(drains[i].max) + " must exceed min " +
                                vecText(drains[i].min) + " on every axis");
    }
    return {};
}

namespace {

// Every block, emitter, collider and the domain, in file order.
Result<void> checkContents(const Scene& scene) {
    const float s = scene.simulation.spacing;
    SceneCheck check(scene);
    checkDomain(check, scene);
    for (std::size_t i = 0; i < scene.blocks.size(); ++i)
        checkBlock(check, scene.blocks[i], "fluid[" + std::to_string(i) + "]", s);
    for (std::size_t i = 0; i < scene.emitters.size(); ++i)
        checkEmitter(check, scene.emitters[i], "emitters[" + std::to_string(i) + "]", s);
    if (scene.colliders.size() > kMaxSceneColliders)
        check.fail(ErrorCode::InvalidArgument, "colliders",
                   std::to_string(scene.colliders.size()) + " colliders, more than the limit " +
                       std::to_string(kMaxSceneColliders));
    for (std::size_t i = 0; i < scene.colliders.size(); ++i)
        checkCollider(check, scene.colliders[i], "colliders[" + std::to_string(i) + "]");
    if (auto ok = checkDrains(scene.drains, "drains"); !ok && check.ok())
        check.fail(ok.error().code, "drains", ok.error().detail);
    if (!check.ok())
        return check.error();
    return {};
}

std::uint64_t blockParticles(const Scene& scene) {
    std::uint64_t n = 0;
    for (const FluidBlock& b : scene.blocks)
        n += blockParticleCount(b, scene.simulation.spacing);
    return n;
}

} // namespace

float defaultKernelRadius(float spacing) {
    return float(kDefaultKernelSpacings) * spacing;
}

float defaultShapeVoxel(float spacing) {
    return 0.5f * spacing;
}

float defaultScorrDeltaQ(float kernelRadius) {
    return static_cast<float>(0.2 * double(kernelRadius));
}

float defaultVorticity(float kernelRadius) {
    return static_cast<float>(0.01 * std::sqrt(9.81 * double(kernelRadius)));
}

std::uint32_t defaultSubsteps(const Scene& scene) {
    const SimulationParams& p = scene.simulation;
    double minY = kInf;
    double maxY = -kInf;
    auto span = [&](double lo, double hi) {
        minY = std::min(minY, lo);
        maxY = std::max(maxY, hi);
    };
    for (const FluidBlock& b : scene.blocks) {
        if (b.shape == FluidBlock::Shape::Box)
            span(b.min.y, b.max.y);
        else
            span(double(b.center.y) - b.radius, double(b.center.y) + b.radius);
    }
    for (const Emitter& e : scene.emitters)
        span(e.position.y, e.position.y);
    if (scene.domainMin && scene.domainMax)
        span(scene.domainMin->y, scene.domainMax->y);
    const double height = maxY > minY ? maxY - minY : 0.0;
    const glm::dvec3 g(p.gravity);
    const double fall = std::sqrt(2.0 * std::sqrt(glm::dot(g, g)) * height);
    double vEst = fall;
    for (const Emitter& e : scene.emitters)
        vEst = std::max(vEst, double(e.speed) + fall);
    for (const FluidBlock& b : scene.blocks) {
        const glm::dvec3 v(b.velocity);
        vEst = std::max(vEst, std::sqrt(glm::dot(v, v)) + fall);
    }
    const double n = std::ceil(double(p.timeStep) * vEst / (kCflNumber * double(p.kernelRadius)));
    if (!(n < double(kMaxDefaultSubsteps)))
        return kMaxDefaultSubsteps;
    return std::max<std::uint32_t>(1, std::uint32_t(n));
}

Result<std::uint32_t> defaultCapacity(const Scene& scene) {
    const SimulationParams& p = scene.simulation;
    const std::uint64_t blocks = blockParticles(scene);
    if (blocks > kMaxSceneParticles)
        return fail(ErrorCode::SizeOverflow, "the fluid blocks hold " + std::to_string(blocks) +
                                                 " particles, more than the limit " +
                                                 std::to_string(kMaxSceneParticles));
    // The layer count in float, as the runtime's emitter schedule computes its interval, so a
    // round duration gives a round count (8 s / 0.02 s = 400, not 400.00001 -> 401).
    double emitted = 0.0;
    for (const Emitter& e : scene.emitters) {
        const std::uint64_t disc = emitterDiscCount(e.radius, p.spacing);
        float interval = p.spacing / e.speed;
        if (e.rate > 0.0f)
            interval = std::max(interval, float(disc) / e.rate);
        const float layers = std::ceil((e.stop - e.start) / interval);
        // A long, fast emitter can pass the float range; double cannot overflow here.
        emitted += (std::isfinite(layers)
                        ? double(layers)
                        : std::ceil((double(e.stop) - double(e.start)) / double(interval))) *
                   double(disc);
    }
    const double total = double(blocks) + emitted;
    if (!(total <= double(kMaxSceneParticles)))
        return fail(ErrorCode::SizeOverflow,
                    "the scene needs " + formatNumber(total) + " particles (" +
                        std::to_string(blocks) + " in fluid blocks + " + formatNumber(emitted) +
                        " from emitters), more than the limit " +
                        std::to_string(kMaxSceneParticles) +
                        "; use a larger spacing, an earlier emitter stop, or set capacity");
    return static_cast<std::uint32_t>(total);
}

Result<void> completeScene(Scene& scene) {
    const std::string label = scene.path.empty() ? "scene" : scene.path;
    if (auto ok = checkLattice(scene); !ok)
        return ok;
    Scene done = scene;
    SimulationParams& p = done.simulation;
    if (p.kernelRadius == 0.0f)
        p.kernelRadius = defaultKernelRadius(p.spacing);
    if (p.scorrDeltaQ == kDerived && std::isfinite(p.kernelRadius))
        p.scorrDeltaQ = defaultScorrDeltaQ(p.kernelRadius);
    if (p.vorticity == kDerived && std::isfinite(p.kernelRadius))
        p.vorticity = defaultVorticity(p.kernelRadius);
    for (SceneCollider& c : done.colliders)
        if (c.shape && c.shape->voxelSize == 0.0f)
            c.shape->voxelSize = defaultShapeVoxel(p.spacing);
    for (Emitter& e : done.emitters)
        if (e.stop == 0.0f && std::isfinite(e.start))
            e.stop = e.start + kDefaultEmitterDuration;
    // The parameters with their counts still to derive held at a valid placeholder, so the one
    // range check (SimulationLimits.h) names any other problem first.
    SimulationParams counted = p;
    counted.substeps = std::max(1u, p.substeps);
    counted.capacity = std::max(1u, p.capacity);
    if (auto ok = checkSimulationParams(counted); !ok)
        return fail(ok.error().code, label + ": simulation." + ok.error().detail);
    if (auto ok = checkContents(done); !ok)
        return ok;
    for (Emitter& e : done.emitters)
        e.direction = glm::vec3(glm::normalize(glm::dvec3(e.direction)));
    if (p.substeps == 0)
        p.substeps = defaultSubsteps(done);
    const std::uint64_t inBlocks = blockParticles(done);
    if (p.capacity == 0) {
        if (done.blocks.empty() && done.emitters.empty())
            return fail(ErrorCode::InvalidArgument,
                        label + ": simulation.capacity: 0 with no fluid blocks and no emitters; "
                                "give the most particles the program will add");
        auto capacity = defaultCapacity(done);
        if (!capacity)
            return fail(capacity.error().code,
                        label + ": simulation.capacity: " + capacity.error().detail);
        p.capacity = *capacity;
    } else if (p.capacity < inBlocks) {
        return fail(ErrorCode::InvalidArgument,
                    label + ": simulation.capacity: " + std::to_string(p.capacity) +
                        " is smaller than the " + std::to_string(inBlocks) +
                        " particles the fluid blocks hold");
    }
    scene = std::move(done);
    return {};
}

} // namespace sluice::format
