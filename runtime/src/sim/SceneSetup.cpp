// Derived PBF constants, initial particles, emitter schedules and collider poses (docs/pbf.md).
#include "sluice/rt/sim/SceneSetup.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/gtc/quaternion.hpp>

#include "sluice/format/scene/SolverReach.h"
#include "sluice/format/support/Assert.h"

namespace sluice::rt {

namespace {

constexpr double kPi = std::numbers::pi;

/// Slack on the lattice-membership tests, in units of the spacing: without it a radius that is
/// a whole number of spacings in decimal (0.06 = 3 * 0.02) would lose its rim to float rounding.
constexpr double kLatticeSlack = 1e-4;

/// poly6 in double (Müller et al. 2003).
double poly6(double q, double h) {
    if (q >= h)
        return 0.0;
    const double d = h * h - q * q;
    return 315.0 / (64.0 * kPi * std::pow(h, 9)) * d * d * d;
}

/// |spiky gradient| magnitude factor: gradW(x) = spikyGradScalar(|x|) * x / |x|.
double spikyGradScalar(double q, double h) {
    if (q <= 0.0 || q >= h)
        return 0.0;
    return -45.0 / (kPi * std::pow(h, 6)) * (h - q) * (h - q);
}

} // namespace

PbfConstants deriveConstants(const format::SimulationParams& params) {
    SLUICE_ASSERT(params.spacing > 0.0f && params.kernelRadius > 0.0f && params.restDensity > 0.0f,
                  "deriveConstants: spacing, kernel radius and rest density must be > 0");
    SLUICE_ASSERT(params.substeps > 0 && params.timeStep > 0.0f,
                  "deriveConstants: time step and substeps must be > 0");
    const double s = params.spacing;
    const double h = params.kernelRadius;
    const double rho0 = params.restDensity;

    // Mass calibration: a particle inside the rest lattice sums to exactly rho0.
    const int K = int(std::ceil(h / s));
    double wSum = 0.0;
    for (int k = -K; k <= K; ++k)
        for (int j = -K; j <= K; ++j)
            for (int i = -K; i <= K; ++i)
                wSum += poly6(s * std::sqrt(double(i * i + j * j + k * k)), h);
    const double mass = rho0 / wSum;
    const double volume = mass / rho0;

    // S_rest = sum_{o != 0} |V gradW(o)|^2; the |sum gradW|^2 term vanishes by symmetry.
    double sRest = 0.0;
    for (int k = -K; k <= K; ++k)
        for (int j = -K; j <= K; ++j)
            for (int i = -K; i <= K; ++i) {
                const double q = s * std::sqrt(double(i * i + j * j + k * k));
                const double g = volume * spikyGradScalar(q, h);
                sRest += g * g;
            }
    const double epsilon = double(params.relaxation) * sRest;

    // Boundary volume calibration (docs/bodies.md): at the rest distance s/2 from a flat
    // boundary, the lattice rows behind it hold this share of the lattice sum; the continuous
    // share B(s/2) of pbf_lambda.comp is scaled to match it, so a particle resting against a
    // body has exactly rho0.
    double behind = 0.0;
    for (int k = -K; k <= -1; ++k)
        for (int j = -K; j <= K; ++j)
            for (int i = -K; i <= K; ++i)
                behind += poly6(s * std::sqrt(double(i * i + j * j + k * k)), h);
    const double u = std::min(0.5 * s / h, 1.0);
    const double u2 = u * u;
    const double share =
        0.5 - (315.0 / 256.0) * u *
                  (1.0 + u2 * (-4.0 / 3.0 + u2 * (6.0 / 5.0 + u2 * (-4.0 / 7.0 + u2 / 9.0))));

    PbfConstants c;
    c.h = float(h);
    c.radius = float(0.5 * s);
    c.mass = float(mass);
    c.volume = float(volume);
    c.sRest = float(sRest);
    c.epsilon = float(epsilon);
    c.lambdaRef = float(1.0 / (sRest + epsilon));
    c.wDeltaQ = float(poly6(params.scorrDeltaQ, h));
    c.poly6 = float(315.0 / (64.0 * kPi * std::pow(h, 9)));
    c.spikyGrad = float(-45.0 / (kPi * std::pow(h, 6)));
    c.dt = float(double(params.timeStep) / double(params.substeps));
    c.boundaryScale = share > 0.0 ? float(behind / wSum / share) : 1.0f;
    c.bodyOffset = float(format::kBodySurfaceOffsetSpacings * s);
    return c;
}

std::vector<ParticleState> fillBlocks(const format::Scene& scene) {
    const double s = scene.simulation.spacing;
    const double r = 0.5 * s;
    std::vector<ParticleState> out;
    std::uint32_t id = 0;
    for (const format::FluidBlock& block : scene.blocks) {
        if (block.shape == format::FluidBlock::Shape::Box) {
            glm::ivec3 n{0};
            for (int a = 0; a < 3; ++a)
                n[a] = std::max(
                    0, int(std::floor((double(block.max[a]) - block.min[a]) / s + kLatticeSlack)));
            const glm::dvec3 lo(block.min);
            for (int k = 0; k < n.z; ++k)
                for (int j = 0; j < n.y; ++j)
                    for (int i = 0; i < n.x; ++i) {
                        const glm::dvec3 p = lo + s * glm::dvec3(i + 0.5, j + 0.5, k + 0.5);
                        out.push_back({glm::vec3(p), block.velocity, id++});
                    }
        } else {
            const double reach = double(block.radius) - r + kLatticeSlack * s;
            if (reach < 0.0)
                continue;
            const int K = int(std::floor(reach / s));
            const glm::dvec3 c(block.center);
            for (int k = -K; k <= K; ++k)
                for (int j = -K; j <= K; ++j)
                    for (int i = -K; i <= K; ++i) {
                        const glm::dvec3 o = s * glm::dvec3(i, j, k);
                        if (glm::length(o) <= reach)
                            out.push_back({glm::vec3(c + o), block.velocity, id++});
                    }
        }
    }
    return out;
}

std::vector<glm::vec3> emitterDisc(const format::Emitter& emitter, float spacing) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(emitter.direction));
    const glm::dvec3 up = std::abs(d.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(d, up));
    const glm::dvec3 w = glm::cross(d, u);
    const double s = spacing;
    const double reach = double(emitter.radius) + kLatticeSlack * s;
    const int A = int(std::floor(reach / s));
    std::vector<glm::vec3> disc;
    for (int b = -A; b <= A; ++b)
        for (int a = -A; a <= A; ++a)
            if (s * std::sqrt(double(a * a + b * b)) <= reach)
                disc.push_back(glm::vec3(s * (double(a) * u + double(b) * w)));
    return disc;
}

EmitterSchedule::EmitterSchedule(const format::Scene& scene) : m_spacing(scene.simulation.spacing) {
    for (const format::Emitter& e : scene.emitters) {
        SLUICE_ASSERT(e.speed > 0.0f, "EmitterSchedule: emitter speed must be > 0");
        Nozzle nozzle;
        nozzle.emitter = e;
        nozzle.disc = emitterDisc(e, m_spacing);
        double interval = double(m_spacing) / e.speed;
        if (e.rate > 0.0f)
            interval = std::max(interval, double(nozzle.disc.size()) / e.rate);
        nozzle.interval = float(interval);
        m_nozzles.push_back(std::move(nozzle));
    }
}

bool EmitterSchedule::emit(float t, std::uint32_t currentCount, std::uint32_t capacity,
                           std::uint32_t& nextId, std::vector<ParticleState>& out) {
    bool allFit = true;
    for (Nozzle& nozzle : m_nozzles) {
        const format::Emitter& e = nozzle.emitter;
        if (!(e.start <= t && t < e.stop))
            continue;
        const double interval = nozzle.interval;
        const auto owed = std::uint64_t(std::floor((double(t) - e.start) / interval)) + 1;
        const glm::dvec3 dir = glm::normalize(glm::dvec3(e.direction));
        const glm::vec3 velocity = glm::vec3(double(e.speed) * dir);
        for (std::uint64_t l = nozzle.emittedLayers; l < owed; ++l) {
            // A layer emitted late has already travelled since its due time.
            const double age = double(t) - (double(e.start) + double(l) * interval);
            const glm::dvec3 centre = glm::dvec3(e.position) + double(e.speed) * age * dir;
            for (const glm::vec3& offset : nozzle.disc) {
                if (std::uint64_t(currentCount) + out.size() >= capacity) {
                    allFit = false;
                    break;
                }
                out.push_back({glm::vec3(centre + glm::dvec3(offset)), velocity, nextId++});
            }
        }
        nozzle.emittedLayers = std::max(nozzle.emittedLayers, owed);
    }
    return allFit;
}

void EmitterSchedule::skip(float t) {
    for (Nozzle& nozzle : m_nozzles) {
        const format::Emitter& e = nozzle.emitter;
        if (!(e.start <= t && t < e.stop))
            continue;
        const auto owed =
            std::uint64_t(std::floor((double(t) - e.start) / double(nozzle.interval))) + 1;
        nozzle.emittedLayers = std::max(nozzle.emittedLayers, owed);
    }
}

bool EmitterSchedule::finished(float t) const {
    return std::all_of(m_nozzles.begin(), m_nozzles.end(),
                       [t](const Nozzle& n) { return t >= n.emitter.stop; });
}

glm::vec3 ColliderPose::toWorld(glm::vec3 local) const {
    return translation + rotation * (scale * local);
}

glm::vec3 ColliderPose::toLocal(glm::vec3 world) const {
    return (glm::conjugate(rotation) * (world - translation)) / scale;
}

glm::quat eulerDegrees(glm::vec3 degrees) {
    const glm::vec3 rad = glm::radians(degrees);
    const glm::quat qx = glm::angleAxis(rad.x, glm::vec3(1, 0, 0));
    const glm::quat qy = glm::angleAxis(rad.y, glm::vec3(0, 1, 0));
    const glm::quat qz = glm::angleAxis(rad.z, glm::vec3(0, 0, 1));
    return qz * qy * qx;
}

ColliderPose interpolatePose(const ColliderPose& from, float t0, const ColliderPose& to, float t1,
                             float t) {
    ColliderPose pose = t <= t0 ? from : to;
    pose.scale = from.scale;
    if (t <= t0 || t >= t1)
        return pose;
    const float a = (t - t0) / (t1 - t0);
    pose.translation = glm::mix(from.translation, to.translation, a);
    pose.rotation = glm::slerp(from.rotation, to.rotation, a);
    return pose;
}

ColliderPose colliderPose(const format::SceneCollider& collider, float t) {
    ColliderPose pose;
    pose.scale = collider.scale;
    const std::vector<format::ColliderKey>& keys = collider.keys;
    if (!keys.empty()) {
        // Clamped outside the key range; linear translation and slerped rotation between keys.
        const auto keyPose = [&](const format::ColliderKey& key) {
            return ColliderPose{key.translation, eulerDegrees(key.rotationDegrees), collider.scale};
        };
        if (t <= keys.front().time)
            return keyPose(keys.front());
        if (t >= keys.back().time)
            return keyPose(keys.back());
        const auto next = std::upper_bound(
            keys.begin(), keys.end(), t,
            [](float time, const format::ColliderKey& key) { return time < key.time; });
        return interpolatePose(keyPose(*(next - 1)), (next - 1)->time, keyPose(*next), next->time,
                               t);
    }
    pose.translation = collider.translation + collider.linearVelocity * t;
    const glm::quat rest = eulerDegrees(collider.rotationDegrees);
    const glm::vec3 w = glm::radians(collider.angularVelocityDegrees); // [rad/s]
    const float speed = glm::length(w);
    if (speed > 0.0f)
        pose.rotation = glm::angleAxis(speed * t, w / speed) * rest;
    else
        pose.rotation = rest;
    return pose;
}

} // namespace sluice::rt
