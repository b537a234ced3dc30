// CPU reference of the PBF substep of docs/pbf.md: plain loops, float state, no GPU.
#pragma once

#include <cstdint>
#include <vector>

#include "sluice/format/ColliderAsset.h"
#include "sluice/format/Scene.h"
#include "sluice/format/SdfSampler.h"
#include "sluice/rt/SceneSetup.h"

namespace sluice::ref {

/// A collider for the reference: its baked asset (not owned; must outlive the ReferencePbf) and
/// its placement in the scene.
struct ReferenceCollider {
    const format::ColliderAsset* asset = nullptr;
    format::SceneCollider placement;
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
    /// colliders, in scene order (scene.colliders itself is not read). Particles past
    /// scene.simulation.capacity are dropped and reported in stats().capacityReached.
    /// Precondition: every SimulationParams field set as readScene sets it.
    ReferencePbf(const format::Scene& scene, std::vector<ReferenceCollider> colliders);

    /// One substep of docs/pbf.md; stats() then describe this substep alone.
    void substep();

    /// scene.simulation.substeps substeps; stats() then describe the whole step.
    void step();

    /// Current particles: x, v and id, in id order (particles are never removed, so the index
    /// is the id).
    const std::vector<rt::ParticleState>& particles() const { return m_particles; }

    /// Test hook: the particles, writable (e.g. to inject a NaN velocity).
    std::vector<rt::ParticleState>& mutableParticles() { return m_particles; }

    /// Start time of the next substep [s].
    float time() const { return timeAt(m_substepIndex); }

    /// Statistics of the last step() or substep().
    const Stats& stats() const { return m_stats; }

    /// The derived constants in use.
    const rt::PbfConstants& constants() const { return m_c; }

    /// min over colliders of the signed distance at `x` [m], posed at time `t` [s]; +inf
    /// without colliders.
    float colliderDistance(glm::vec3 x, float t) const;

private:
    struct Collider {
        format::SceneCollider placement;
        format::SdfSampler sampler;
    };

    float timeAt(std::uint64_t substepIndex) const;
    void substepImpl();
    void buildNeighbours();
    void solve();
    void collide(glm::vec3& x, glm::vec3 xOld, float t0, float t1) const;
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
    rt::EmitterSchedule m_schedule;
    std::uint32_t m_nextId = 0;
    std::uint64_t m_substepIndex = 0;

    std::vector<rt::ParticleState> m_particles;
    std::vector<glm::vec3> m_predicted;          // x*
    std::vector<std::uint32_t> m_neighbourStart; // CSR: neighbours of i at [start[i], start[i+1])
    std::vector<std::uint32_t> m_neighbours;
    std::vector<float> m_lambda;
    std::vector<float> m_constraint; // C_i of the last lambda pass

    Stats m_stats;
};

} // namespace sluice::ref
