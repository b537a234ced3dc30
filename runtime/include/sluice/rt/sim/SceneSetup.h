// CPU-side scene setup shared by the GPU solver and the CPU reference: derived PBF constants,
// initial particles, emitter schedules and collider placement (docs/pbf.md).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "sluice/format/scene/Scene.h"

namespace sluice::rt {

/// Constants derived from the simulation parameters (docs/pbf.md, "Symbols").
struct PbfConstants {
    float h = 0.0f;          ///< kernel radius [m]
    float radius = 0.0f;     ///< particle radius = spacing / 2 [m]
    float mass = 0.0f;       ///< particle mass calibrated on the rest lattice [kg]
    float volume = 0.0f;     ///< mass / rho0 [m^3]
    float sRest = 0.0f;      ///< sum |V gradW|^2 of a full-neighbourhood particle [1/m^2]
    float epsilon = 0.0f;    ///< lambda relaxation, relaxation * sRest [1/m^2]
    float lambdaRef = 0.0f;  ///< 1 / (sRest + epsilon) [m^2]
    float wDeltaQ = 0.0f;    ///< W(scorrDeltaQ) [1/m^3]
    float poly6 = 0.0f;      ///< 315 / (64 pi h^9)
    float spikyGrad = 0.0f;  ///< -45 / (pi h^6)
    float dt = 0.0f;         ///< substep length timeStep / substeps [s]
    /// Scale of a body's boundary volume: the rest lattice's share behind a flat boundary at
    /// s/2 over the continuous share there (docs/bodies.md)
    float boundaryScale = 1.0f;
    /// A dynamic body's fluid-facing surface lies this far inside its zero level set, 0.05
    /// spacing (format::kBodySurfaceOffsetSpacings): the first fluid layer sits about that much
    /// further out than the contact distance (docs/bodies.md, "Surface offset") [m]
    float bodyOffset = 0.0f;
};

/// Computes PbfConstants in double precision. Precondition: params as readScene returns them.
PbfConstants deriveConstants(const format::SimulationParams& params);

/// One particle as the CPU sees it.
struct ParticleState {
    glm::vec3 position{0.0f}; ///< [m]
    glm::vec3 velocity{0.0f}; ///< [m/s]
    std::uint32_t id = 0;     ///< creation order, stable across steps
};

/// The particles of the scene's fluid blocks, in the order docs/pbf.md defines, ids from 0.
std::vector<ParticleState> fillBlocks(const format::Scene& scene);

/// Disc points of one emitter layer relative to its centre (docs/pbf.md step 1), in order.
std::vector<glm::vec3> emitterDisc(const format::Emitter& emitter, float spacing);

/// Tracks which layers each emitter has emitted.
class EmitterSchedule {
public:
    explicit EmitterSchedule(const format::Scene& scene);

    /// Appends the particles owed at substep time `t` [s] to `out`, ids continuing from
    /// `nextId`, never letting `currentCount + out.size()` pass `capacity`. Returns false if
    /// some owed particle did not fit (the capacity was reached).
    bool emit(float t, std::uint32_t currentCount, std::uint32_t capacity, std::uint32_t& nextId,
              std::vector<ParticleState>& out);

    /// Marks every layer owed at substep time `t` [s] as emitted without emitting it: while the
    /// emitters are off, so switching them on does not release the layers due meanwhile.
    void skip(float t);

    /// True once every emitter has stopped (no more particles will ever come).
    bool finished(float t) const;

private:
    struct Nozzle {
        format::Emitter emitter;
        std::vector<glm::vec3> disc;
        float interval = 0.0f;
        std::uint64_t emittedLayers = 0;
    };
    std::vector<Nozzle> m_nozzles;
    float m_spacing = 0.0f;
};

/// A collider's rigid placement at one time: world = translation + rotation * (scale * local).
struct ColliderPose {
    glm::vec3 translation{0.0f}; ///< [m]
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    float scale = 1.0f;

    glm::vec3 toWorld(glm::vec3 local) const;
    glm::vec3 toLocal(glm::vec3 world) const;
};

/// The pose between `from` at time `t0` and `to` at `t1` > t0 [s]: `from` up to t0, `to` from
/// t1 on, translation linear and rotation slerped between; the scale is `from`'s. Keyframes and the
/// poses a program sets (Simulation::setColliderPose) both move by it, so the same motion gives the
/// same bits.
ColliderPose interpolatePose(const ColliderPose& from, float t0, const ColliderPose& to, float t1,
                             float t);

/// The pose of `collider` at time `t` [s] (docs/pbf.md, "Collision").
ColliderPose colliderPose(const format::SceneCollider& collider, float t);

/// Rotation from Euler degrees X, Y, Z applied Rz * Ry * Rx.
glm::quat eulerDegrees(glm::vec3 degrees);

} // namespace sluice::rt
