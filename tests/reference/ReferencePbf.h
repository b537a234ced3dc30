// CPU reference of the PBF substep of docs/pbf.md and docs/bodies.md: plain loops, float state,
// no GPU.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "shared/Bodies.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/rt/sim/SceneSetup.h"

namespace sluice::ref {

/// Whether every component of v is finite.
inline bool isFinite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// A collider for the reference: its baked asset (not owned; must outlive the ReferencePbf) and
/// its placement in the scene. With placement.dynamic set it is a rigid body (docs/bodies.md),
/// held at one pose: it fills part of the kernel support of the particles near it, pushes them,
/// and takes the reaction; the reference does not move it.
/// The gradient of a collider's trilinear field at local point p [1 per asset unit], in the cell
/// the GPU's float arithmetic puts p in, the values and the derivative in double.
glm::dvec3 gradientInTheGpusCell(const format::SdfSampler& sampler, glm::vec3 p);

struct ReferenceCollider {
    const format::ColliderAsset* asset = nullptr;
    format::SceneCollider placement;
    /// Bodies only: the centre of mass, world [m]. The reaction's moment arms x - c, and so
    /// ReferencePbf::bodyTorque, are about it.
    glm::vec3 centerOfMass{0.0f};
    /// Bodies only: the pose the body is held at; unset, the placement's pose at t = 0.
    std::optional<rt::ColliderPose> bodyPose;
    /// Bodies only: its mass [kg] and velocity at the substep start [m/s], which decide how much
    /// of the held particles' reaction it takes (docs/bodies.md, "Particles held against a
    /// wall"); a mass of 0 takes none of it.
    double mass = 0.0;
    glm::vec3 linearVelocity{0.0f};
    /// Bodies only: its angular velocity at the substep start [rad/s] and inverse inertia about
    /// the centre of mass, both in the world at `bodyPose` [1/(kg m^2)]. The held
    /// particles' contact is taken where it acts, with the body's spin and effective mass there
    /// (pbf_bodies.comp, takeHeldReaction); a zero inverse inertia takes it at the centre.
    glm::vec3 angularVelocity{0.0f};
    glm::mat3 invInertia{0.0f};
    /// Bodies only: its contact points in the asset frame [asset units], `w` the area each
    /// stands for [asset units^2] (what rt::surfacePoints gives the GPU). The points sealed
    /// against a wall or a static collider take the water's pressure there (docs/bodies.md,
    /// "Sealed contacts"); none, no sealed contacts.
    std::vector<glm::vec4> contactPoints;
};

/// Runs the PBF step of docs/pbf.md on the CPU, one particle at a time, as the contract the GPU
/// solver is compared against (by particle id).
///
/// State is float like the GPU's; kernel sums are float. Constants come from rt::deriveConstants,
/// initial particles from rt::fillBlocks, emission from rt::EmitterSchedule and collider
/// placement from rt::colliderPose; the kernels, the neighbour search (a hash map of cells of
/// size h, then the exact |d| < h test) and the solver are written here, independently of the
/// shaders.
///
/// Time: substep n (from 0) starts at t = float(n * double(dt)), computed, not accumulated.
///
/// Dynamic bodies (docs/bodies.md) are on only for colliders whose placement has `dynamic`:
/// the blocks' particles whose centre starts inside one are left out (ids keep the blocks'
/// numbering), its boundary volume joins the density constraint, its boundary push and its
/// push-out and friction are summed per body in double as sum dx and sum (x - c) x dx, and
/// bodyForce / bodyTorque turn them into the fluid's force and torque. The body stays at its
/// pose: the reference checks the fluid's side and the reaction of a substep, not the body's
/// motion (pbf_bodies.comp's integration and contacts).
class ReferencePbf {
public:
    /// Statistics of the last step() (or of the last substep() when called alone), as
    /// docs/pbf.md "Statistics" defines them.
    struct Stats {
        double avgDensityError = 0.0;            ///< mean C_i of the last lambda pass
        double maxDensityError = 0.0;            ///< max C_i of the last lambda pass
        double maxSpeed = 0.0;                   ///< max |v_i| at the end [m/s]
        std::uint32_t insideColliders = 0;       ///< particles with min phi < -r/2 at the end
        std::uint32_t nonFinite = 0;             ///< step-5 resets, summed over the substeps
        std::uint32_t iterationsLastSubstep = 0; ///< position updates in the last substep
        bool capacityReached = false;            ///< some owed particle did not fit
    };

    /// Sets up the scene's blocks (ids from 0) at t = 0. `colliders` stand for the scene's
    /// colliders, in scene order (scene.colliders itself is not read). Particles whose centre
    /// starts inside a dynamic body (phi < 0 at its placement's pose at t = 0) are left out;
    /// then particles past scene.simulation.capacity are dropped and reported in
    /// stats().capacityReached.
    /// Precondition: every SimulationParams field set as readScene sets it.
    ReferencePbf(const format::Scene& scene, std::vector<ReferenceCollider> colliders);

    /// One substep of docs/pbf.md; stats() then describe this substep alone.
    void substep();

    /// scene.simulation.substeps substeps; stats() then describe the whole step.
    void step();

    /// Current particles: x, v and id, in id order. Particles are never removed during the run,
    /// so the index is the id, except when dynamic bodies left particles out at the start.
    const std::vector<rt::ParticleState>& particles() const { return m_particles; }

    /// Test hook: the particles, writable (e.g. to inject a NaN velocity).
    std::vector<rt::ParticleState>& mutableParticles() { return m_particles; }

    /// Start time of the next substep [s].
    float time() const { return timeAt(m_substepIndex); }

    /// Statistics of the last step() or substep().
    const Stats& stats() const { return m_stats; }

    /// The derived constants in use.
    const rt::PbfConstants& constants() const { return m_c; }

    /// min over colliders of the signed distance at `x` [m], posed at time `t` [s] (bodies at
    /// their held pose, from their zero level set); +inf without colliders.
    float colliderDistance(glm::vec3 x, float t) const;
    /// The walls' and static colliders' boundary share at `x` now (w) and its gradient (xyz),
    /// as rt::Simulation::solidBoundaryAt gives it.
    glm::vec4 solidBoundaryAt(glm::vec3 x) const;

    /// Dynamic bodies, in scene order of their colliders.
    std::size_t bodyCount() const { return m_bodies.size(); }

    /// The fluid's force on body `b` [N]: F = -m sum dx / dt^2 over every correction the body
    /// gave a particle in the last substep (boundary push, push-out and friction), m the
    /// particle mass, dt the substep; after step(), the mean over its substeps.
    glm::dvec3 bodyForce(std::size_t b) const;

    /// The fluid's torque on body `b` about its centre of mass [N m]:
    /// -m sum (x - c) x dx / dt^2, x the particle's position after the correction dx; after
    /// step(), the mean over its substeps.
    glm::dvec3 bodyTorque(std::size_t b) const;
    /// The force the particles a domain wall held against body b would have given it, before
    /// the share that only stops the body (of the last step(), as bodyForce) [N].
    glm::dvec3 bodyHeldForce(std::size_t b) const;
    /// The part of bodyForce(b) that the water sealed under body b's contacts gave it
    /// (docs/bodies.md, "Sealed contacts") [N].
    glm::dvec3 bodySealedForce(std::size_t b) const;

    /// Particles of the blocks left out because their centre started inside a body.
    std::uint32_t particlesRemovedAtSpawn() const { return m_removedAtSpawn; }

private:
    static constexpr std::uint32_t kNoBody = 0xffffffffu;

    struct Collider {
        format::SceneCollider placement;
        format::SdfSampler sampler;
        std::uint32_t body = kNoBody; // index into m_bodies, or kNoBody
        const format::ColliderAsset* asset = nullptr;
        std::vector<float> volumeMap; // static colliders: per grid point (docs/pbf.md)
    };

    /// A dynamic body: where it is held and its reaction sums.
    struct Body {
        std::size_t collider = 0;
        rt::ColliderPose pose;
        glm::vec3 centerOfMass{0.0f};
        double mass = 0.0;
        glm::dvec3 velocity{0.0};             // at the substep start [m/s]
        glm::dvec3 angularVelocity{0.0};      // at the substep start, world [rad/s]
        glm::dmat3 invInertia{0.0};           // world, at `pose` [1/(kg m^2)]
        glm::dvec3 sumDx{0.0};                // sum dx of the current substep [m]
        glm::dvec3 sumMoment{0.0};            // sum (x - c) x dx of the current substep [m^2]
        glm::dvec3 heldDx{0.0};               // the collision pushes a domain wall undid [m]
        glm::dvec3 heldMoment{0.0};           // [m^2]
        glm::dvec3 heldForce{0.0};            // of heldDx, before the share [N]
        std::vector<glm::vec4> contactPoints; // asset frame; w: area [asset units^2]
        glm::dvec3 underDx{0.0};              // its pushes across a solid in its rim band [m]
        glm::dvec3 underMoment{0.0};          // their moments (x - c) x dx [m^2]
        double boundRadius = 0.0;    // as the GPU's: contact points' reach + a voxel [m]
        std::uint32_t surface = 0;   // the film model's level word (FilmGlsl.h)
        glm::dvec3 filmDx{0.0};      // what the film model took off the water under
        glm::dvec3 filmMoment{0.0};  // it, given back as far as it holds the approach
        glm::dvec3 sealedForce{0.0}; // of the sealed contacts, in force [N]
        glm::dvec3 force{0.0};       // of the last substep, or the mean over the last step [N]
        glm::dvec3 torque{0.0};      // [N m]
    };

    float timeAt(std::uint64_t substepIndex) const;
    void substepImpl(double bodyShare);
    void buildNeighbours();
    void solve();
    void removeParticlesInBodies();
    bool bodyBoundary(const Body& body, glm::vec3 x, float& phi, glm::vec3& normal) const;
    float boundaryShare(float phi) const;
    /// docs/pbf.md, "Volume maps": a static collider's map for the kernel support `support`
    /// [asset units], one value per grid point; empty for a grid too large for one.
    static std::vector<float> buildVolumeMap(const format::ColliderAsset& asset,
                                             const format::SdfSampler& sampler, double support);
    /// The map of c at local point q, trilinear; `grad` its gradient per asset unit.
    double volumeCorrection(const Collider& c, glm::dvec3 q, glm::dvec3& grad) const;
    float boundaryShareSlope(float phi) const;
    void addSolidBoundary(glm::vec3 x, float t1, float& boundary, glm::vec3& gradient) const;
    double nearestSolidWithin(glm::vec3 x, double limit, float t1, glm::dvec3& normal) const;
    /// A body's contact point within `band` of a wall or a static collider: where it is, the
    /// gap, the solid's normal and the body's (in the GPU's cell), and the area it stands for.
    struct PointOverSolid {
        glm::vec3 world{0.0f};
        double gap = 0.0;
        glm::dvec3 solidNormal{0.0};
        glm::dvec3 normal{0.0};
        double area = 0.0; // [m^2]
    };
    bool pointOverSolid(const Body& body, const glm::vec4& point, double band, float t1,
                        PointOverSolid& out) const;
    double sealedBand() const;
    double rimBand() const;
    void addRim(Body& body, glm::vec3 x, glm::vec3 dx);
    void recordSurface(glm::vec3 x);
    void addFilm(Body& body, float t1);
    double surfaceBase(const Body& body) const;
    /// A body's velocity within a substep, as pbf_bodies.comp's BodyStart holds it.
    struct BodyMotion {
        glm::dvec3 v{0.0};
        glm::dvec3 w{0.0};
    };
    void takeStopping(Body& body, glm::dvec3 impulse, glm::dvec3 angular, double allowed,
                      bool atPoint, double share, BodyMotion& motion);
    void addReaction(Body& body, glm::vec3 x, glm::vec3 dx);
    void addHeld(Body& body, glm::vec3 x, glm::vec3 dx);
    void startBodyStep();
    void finishBodySubstep(double share);
    /// The body whose push-out moved a particle in collide(), and the sum of those pushes.
    struct Pushed {
        std::uint32_t body = kNoBody;
        glm::vec3 sum{0.0f};
    };
    void collide(glm::vec3& x, glm::vec3 xOld, float t0, float t1, Pushed& pushed);
    float constraintAndLambda(std::size_t i, const std::vector<float>& pairW,
                              const std::vector<glm::vec3>& pairGrad, float t1);
    glm::vec3 applyCorrection(std::size_t i, glm::vec3 dp, glm::vec3 xOld, float t0, float t1);
    void vorticityAndXsph(std::vector<glm::vec3>& velocity) const;
    void finishStats();

    // Kernels (Müller et al. 2003), float like the GPU.
    float W(float q) const;
    glm::vec3 gradW(glm::vec3 x) const;

    format::SimulationParams m_params;
    rt::PbfConstants m_c;
    bool m_hasDomain = false;
    glm::vec3 m_domainMin{0.0f}, m_domainMax{0.0f};
    std::vector<Collider> m_colliders;
    std::vector<Body> m_bodies;
    float m_bodyOffset = 0.0f; // bodies' fluid-facing surface lies this far inside phi = 0 [m]
    std::uint32_t m_removedAtSpawn = 0;
    rt::EmitterSchedule m_schedule;
    std::uint32_t m_nextId = 0;
    std::uint64_t m_substepIndex = 0;
    bool m_inRim = false;        // the particle being corrected is in the rim band of a solid
    glm::dvec3 m_rimNormal{0.0}; // and that solid's normal

    std::vector<rt::ParticleState> m_particles;
    std::vector<glm::vec3> m_predicted;          // x*
    std::vector<std::uint32_t> m_neighbourStart; // CSR: neighbours of i at [start[i], start[i+1])
    std::vector<std::uint32_t> m_neighbours;
    std::vector<float> m_lambda;
    std::vector<float> m_constraint; // C_i of the last lambda pass

    Stats m_stats;
};

} // namespace sluice::ref
