// libFuzzer target: the scene reader (parseScene) on untrusted JSON text.
//
// An accepted scene must satisfy what SceneIO.h and Scene.h promise and what the runtime's
// CPU-side setup assumes (rt::deriveConstants, rt::fillBlocks, rt::EmitterSchedule and
// rt::colliderPose, compiled in from runtime/src/sim/SceneSetup.cpp): the particle count the reader
// sized the capacity with is the count the runtime creates. No single allocation may exceed
// what the text's size justifies.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "FuzzSupport.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/rt/sim/SceneSetup.h"

namespace {

using namespace sluice;
using namespace sluice::format;

constexpr const char* kName = "fuzz/scene.json";

/// Blocks up to this many particles are also enumerated by rt::fillBlocks [particles].
constexpr std::uint64_t kEnumerateLimit = 20'000;

bool finite(float v) {
    return std::isfinite(v);
}
bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void checkAccepted(const Scene& scene) {
    const SimulationParams& p = scene.simulation;
    SLUICE_FUZZ_CHECK(finite(p.spacing) && p.spacing > 0.0f, "spacing > 0");
    SLUICE_FUZZ_CHECK(finite(p.kernelRadius) && p.kernelRadius >= p.spacing, "h >= spacing");
    SLUICE_FUZZ_CHECK(finite(p.restDensity) && p.restDensity > 0.0f, "rest density > 0");
    SLUICE_FUZZ_CHECK(finite(p.timeStep) && p.timeStep > 0.0f, "time step > 0");
    SLUICE_FUZZ_CHECK(p.substeps >= 1, "substeps derived");
    SLUICE_FUZZ_CHECK(p.minIterations >= 1 && p.maxIterations >= p.minIterations, "iterations");
    SLUICE_FUZZ_CHECK(finite(p.gravity) && finite(p.xsph) && finite(p.vorticity) &&
                          finite(p.scorrK) && finite(p.scorrN) && finite(p.scorrDeltaQ) &&
                          finite(p.relaxation) && finite(p.targetDensityError),
                      "parameters finite");
    SLUICE_FUZZ_CHECK(p.capacity >= 1 && p.capacity <= kMaxSceneParticles, "capacity range");
    SLUICE_FUZZ_CHECK(scene.colliders.size() <= kMaxSceneColliders, "collider limit");
    SLUICE_FUZZ_CHECK(!scene.blocks.empty() || !scene.emitters.empty(), "something to simulate");
    SLUICE_FUZZ_CHECK(scene.domainMin.has_value() == scene.domainMax.has_value(), "domain pair");

    std::uint64_t blockParticles = 0;
    for (const FluidBlock& b : scene.blocks) {
        SLUICE_FUZZ_CHECK(finite(b.min) && finite(b.max) && finite(b.center) && finite(b.radius) &&
                              finite(b.velocity),
                          "block finite");
        const std::uint64_t n = blockParticleCount(b, p.spacing);
        SLUICE_FUZZ_CHECK(n >= 1 && n <= kMaxSceneParticles, "block holds particles");
        blockParticles += n;
    }
    SLUICE_FUZZ_CHECK(blockParticles <= p.capacity, "capacity holds the blocks");
    for (const Emitter& e : scene.emitters) {
        SLUICE_FUZZ_CHECK(finite(e.position) && finite(e.direction) && finite(e.radius) &&
                              finite(e.speed) && finite(e.rate) && finite(e.start) &&
                              finite(e.stop),
                          "emitter finite");
        const double length = std::sqrt(glm::dot(glm::dvec3(e.direction), glm::dvec3(e.direction)));
        SLUICE_FUZZ_CHECK(std::abs(length - 1.0) < 1e-5, "emitter direction is a unit vector");
        SLUICE_FUZZ_CHECK(e.speed > 0.0f && e.stop > e.start && e.rate >= 0.0f, "emitter ranges");
        SLUICE_FUZZ_CHECK(e.radius >= 0.5f * p.spacing, "emitter radius");
    }
    for (const SceneCollider& c : scene.colliders) {
        SLUICE_FUZZ_CHECK(!c.asset.empty() && !c.resolvedPath.empty(), "collider path");
        SLUICE_FUZZ_CHECK(finite(c.scale) && c.scale > 0.0f, "collider scale");
        SLUICE_FUZZ_CHECK(c.friction >= 0.0f && c.friction <= 1.0f, "collider friction");
        for (std::size_t k = 1; k < c.keys.size(); ++k)
            SLUICE_FUZZ_CHECK(c.keys[k].time > c.keys[k - 1].time, "key times increase");
        if (c.dynamic) {
            const DynamicBody& d = *c.dynamic;
            SLUICE_FUZZ_CHECK(d.density.has_value() != d.mass.has_value(),
                              "a body has exactly one of density and mass");
            const float amount = d.density ? *d.density : *d.mass;
            SLUICE_FUZZ_CHECK(finite(amount) && amount > 0.0f, "body density or mass > 0");
            SLUICE_FUZZ_CHECK(finite(d.linearVelocity) && finite(d.angularVelocityDegrees),
                              "body velocities finite");
            SLUICE_FUZZ_CHECK(d.friction >= 0.0f && d.friction <= 2.0f && d.restitution >= 0.0f &&
                                  d.restitution <= 1.0f,
                              "body friction and restitution ranges");
            SLUICE_FUZZ_CHECK(c.keys.empty() && c.linearVelocity == glm::vec3(0.0f) &&
                                  c.angularVelocityDegrees == glm::vec3(0.0f),
                              "a dynamic collider has no motion");
        }
        // The runtime places it at any time without producing NaN.
        for (const float t : {0.0f, 0.5f, 3.0f}) {
            const rt::ColliderPose pose = rt::colliderPose(c, t);
            SLUICE_FUZZ_CHECK(std::isfinite(pose.scale), "pose scale finite");
        }
    }

    // The runtime's CPU setup accepts the scene: constants derive, schedules build, and the
    // blocks hold exactly the particles the reader counted when it sized the capacity.
    const rt::PbfConstants k = rt::deriveConstants(p);
    SLUICE_FUZZ_CHECK(std::isfinite(k.mass) && k.mass > 0.0f, "particle mass finite and > 0");
    SLUICE_FUZZ_CHECK(std::isfinite(k.poly6) && std::isfinite(k.spikyGrad) &&
                          std::isfinite(k.lambdaRef) && k.dt > 0.0f,
                      "kernel constants finite");
    std::uint64_t discs = 0;
    for (const Emitter& e : scene.emitters)
        discs += emitterDiscCount(e.radius, p.spacing);
    if (discs <= kEnumerateLimit) {
        rt::EmitterSchedule schedule(scene);
        std::uint32_t nextId = 0;
        std::vector<rt::ParticleState> emitted;
        schedule.emit(0.0f, 0, p.capacity, nextId, emitted);
        SLUICE_FUZZ_CHECK(emitted.size() <= p.capacity, "emitters respect the capacity");
    }
    if (blockParticles <= kEnumerateLimit) {
        const std::vector<rt::ParticleState> particles = rt::fillBlocks(scene);
        SLUICE_FUZZ_CHECK(particles.size() == blockParticles,
                          "rt::fillBlocks makes as many particles as blockParticleCount counts");
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    SceneReadOptions options;
    options.checkAssets = false;
    Scene accepted;
    bool ok = false;
    {
        fuzz::AllocationWatch watch;
        Result<Scene> r = parseScene(text, kName, options);
        // A JSON DOM holds ~16 bytes per value, and a value takes at least 2 bytes of text;
        // rapidjson's pool and stack grow in 64 KiB chunks and by doubling.
        watch.check(16 * size + (std::size_t(1) << 20), "parseScene");
        ok = fuzz::takeResult(r, accepted, kName);
    }
    if (ok)
        checkAccepted(accepted);
    return 0;
}
