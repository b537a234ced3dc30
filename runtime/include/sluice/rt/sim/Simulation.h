// The PBF solver on the GPU: particle buffers, the neighbour sort and the solver passes
// (docs/pbf.md), stepped without CPU-GPU synchronisation inside a step.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/format/support/Result.h"
#include "sluice/rt/sim/GpuCommandCount.h"
#include "sluice/rt/sim/SceneSetup.h"

namespace sluice::gpu {
class Buffer; // sluice/gpu/Buffer.h: this header stays free of GL, for a game's own loader
} // namespace sluice::gpu

namespace sluice::rt {

/// How a Simulation runs.
struct SimulationOptions {
    /// Restore a fixed particle order inside every hash bucket after the counting sort, so two
    /// runs give identical bytes (costs one short pass per substep).
    bool deterministic = false;
    /// Time every pass group with GL timer queries (read back without stalling): for --bench,
    /// sluice-play's statistics and the viewer's profiler; a game leaves them off.
    bool timers = false;
    /// Invocations of each body's work group in the body pass (docs/bodies.md), which split its
    /// contact points: 0 picks for the renderer, 8 on a software one (one SIMD vector) and 128 on
    /// a GPU; a power of two from 8 to 512 forces a layout, as the tests do to run the GPU's on
    /// llvmpipe.
    std::uint32_t bodyGroupSize = 0;
    /// Invocations per particle in the neighbour passes (lambda, delta, vorticity,
    /// confinement), which split its candidates and add their sums in a fixed order: 0 picks 1
    /// on a software renderer and, on a GPU, the most (up to 8) for which the capacity times
    /// the lanes stays within kNeighbourLanesTarget; 1, 2, 4, 8, 16 or 32 force it. A
    /// --deterministic run gives the same bytes for the same lanes.
    std::uint32_t neighbourLanes = 0;
    /// Read the colliders' dense samples and volume maps from the SDF buffer's storage block,
    /// as the passes do only where the buffer holds more texels than the GL's texel-buffer limit
    /// (otherwise they fetch them through its texel view): the same bits, for the tests.
    bool sdfFromStorage = false;
    /// Read what the neighbour passes read at other particles' indices (positions, velocities,
    /// masks, cell ranges) from the storage blocks, as they do only where a buffer holds more
    /// texels than the GL's texel-buffer limit (otherwise they fetch through texel views): the
    /// same bits, for the tests.
    bool neighboursFromStorage = false;
};

/// Invocations the automatic neighbour lanes fill at most on a GPU: on an H200, 15k particles ran
/// fastest at 4 lanes (60k invocations), slower at 8 and 16 (docs/performance.md).
inline constexpr std::uint32_t kNeighbourLanesTarget = 1u << 16;

/// The pass groups timed per step, in order.
enum class Pass : std::uint32_t {
    Emit,
    Predict,
    Sort,
    Solve, ///< and step 5, the velocities, in the dispatch that ends it
    Vorticity,
    Bodies,
    Stats,
    Count
};

/// Short name of a pass ("sort").
const char* passName(Pass pass);

/// What one step did, read back after it (docs/pbf.md, "Statistics").
struct StepStats {
    std::uint64_t step = 0; ///< steps completed
    double time = 0.0;      ///< simulated time after the step [s]
    std::uint32_t particles = 0;
    double avgDensityError = 0.0; ///< mean rho/rho0 - 1, compression only, last lambda pass
    double maxDensityError = 0.0;
    double maxSpeed = 0.0;             ///< [m/s]
    std::uint32_t insideColliders = 0; ///< particles with phi < -0.5 r in some collider
    std::uint32_t nonFinite = 0;       ///< particles reset this step because they went non-finite
    std::uint32_t iterations = 0;      ///< solver iterations of the last substep
    double meanIterations = 0.0;       ///< solver iterations per substep, mean over the step
    /// Particle-substeps of this step whose candidate entries outnumbered the neighbour mask's
    /// bits (shared::kNeighbourMaskBits): the candidates past it were tested in full, so the
    /// results are the same, only slower. Never a neighbour lost.
    std::uint32_t maskOverflow = 0;
    std::uint32_t maxCandidates = 0; ///< most candidate entries of one particle (this step)
    std::uint32_t maxNeighbours = 0; ///< most neighbours of one particle (this step)
    /// Lambda and delta dispatches of this step that launched work groups (the ones after an
    /// early stop launch none).
    std::uint32_t solveDispatches = 0;
    bool capacityReached = false; ///< an emitter could not add particles this step
    /// Dynamic bodies put back to their pose at the start of a substep, at rest, because their
    /// state went non-finite or their centre of mass left the domain box: a count since the
    /// simulation started (a body the solver lost; `--check` fails on it).
    std::uint32_t bodyFaults = 0;
};

/// One dynamic body as the GPU holds it after a step (docs/bodies.md).
struct BodyState {
    std::uint32_t collider = 0; ///< its index in the scene's colliders
    double mass = 0.0;          ///< [kg]
    double volume = 0.0;        ///< [m^3]
    bool massFromMesh = false;  ///< mass properties from the mesh (else from the field)
    glm::vec3 position{0.0f};   ///< centre of mass [m]
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f}; ///< asset frame -> world
    glm::vec3 linearVelocity{0.0f};                ///< [m/s]
    glm::vec3 angularVelocity{0.0f};               ///< [rad/s], world
    glm::vec3 force{0.0f};  ///< the fluid's force, mean over the last step [N]
    glm::vec3 torque{0.0f}; ///< the fluid's torque about the centre of mass, mean [N m]
    /// The fluid's upward force over the weight of water the whole body would displace:
    /// Archimedes' submerged share (mean over the last step; 0 out of the water).
    double submergedShare = 0.0;
    std::uint32_t contacts = 0; ///< contact points touching a wall, collider or body
    bool kinematic = false;     ///< the game moves it (Simulation::setBodyKinematic)
    float contactDepth = 0.0f;  ///< deepest of them before correction [m]
    ColliderPose pose;          ///< where the asset frame is: world = pose.toWorld(local)
};

/// A mouse spring on a dynamic body (the viewer's drag): its point `anchor` is pulled towards
/// `target` by a critically damped spring, about 3 Hz whatever the body's mass.
struct BodyDrag {
    std::uint32_t body = 0; ///< index into bodies()
    glm::vec3 anchor{0.0f}; ///< the grabbed point, asset frame [asset units]
    glm::vec3 target{0.0f}; ///< where it is pulled [m]
};

/// Where a ray meets a dynamic body (Simulation::pickBody).
struct BodyHit {
    std::uint32_t body = 0; ///< index into bodies()
    glm::vec3 point{0.0f};  ///< world [m]
    glm::vec3 anchor{0.0f}; ///< the same point in the body's asset frame [asset units]
    float distance = 0.0f;  ///< along the ray [m]
};

/// The particle buffers after a step, as a renderer or a game draws them (docs/embedding.md):
/// GL buffer names, valid until the next step() or addParticles(). The names alternate between
/// two sets from step to step (the neighbour sort ping-pongs), so take the view each frame.
/// Slot i of each buffer is one particle; slots are re-sorted every substep, and `ids` says
/// which particle each slot holds. A slot whose position has w = 1 holds a removed particle
/// not yet compacted away (for a step or two after a removal): skip it.
struct ParticleView {
    std::uint32_t positions = 0;  ///< vec4 per slot: xyz the position [m], w unused
    std::uint32_t velocities = 0; ///< vec4 per slot: xyz the velocity [m/s], w the density error
    std::uint32_t ids = 0;        ///< uint per slot: the particle's id (creation order)
    std::uint32_t count = 0;      ///< slots in use, from 0
    std::uint32_t positionStride = 16; ///< [bytes]
    std::uint32_t velocityStride = 16; ///< [bytes]
    std::uint32_t idStride = 4;        ///< [bytes]
    /// GL buffer holding a DrawArraysIndirectCommand {live particles, 1, 0, 0} for
    /// glDrawArraysIndirect: the live particles lead the slots, so it draws them and no removed
    /// one, its count written on the GPU after each step (particles added since draw from the
    /// next step once any was removed).
    std::uint32_t drawArgs = 0;
};

/// Buffers the game owns that Simulation::copyParticlesById fills: entry k is the particle with
/// id firstId + k.
struct ParticleCopyTarget {
    std::uint32_t positions = 0;  ///< GL buffer of at least 16 count bytes: vec4 per entry, xyz
                                  ///< [m], w 1 where that particle is live, else all 0
    std::uint32_t velocities = 0; ///< GL buffer as `positions` (xyz [m/s]), or 0 for none
    std::uint32_t firstId = 0;    ///< the id of entry 0
    std::uint32_t count = 0;      ///< entries
};

/// How a simulation's volume maps were made (Simulation::volumeMapLoad).
struct VolumeMapLoad {
    std::uint32_t baked = 0; ///< taken from the assets, baked for the scene's kernel radius
    std::uint32_t built = 0; ///< computed on the GPU
    double seconds = 0.0;    ///< at load: the wall time of building them (0 when none was)
    std::vector<std::uint32_t> builtFor; ///< the colliders whose map was built, ascending
};

/// The dynamic bodies as a completed step left them (Simulation::latestBodies).
struct BodiesReading {
    std::uint64_t step = 0; ///< the step they are from (Simulation::steps() after it)
    double time = 0.0;      ///< simulated time after that step [s]
    std::vector<BodyState> bodies;
};

/// The fluid's force on a static or kinematic collider whose force is measured
/// (Simulation::measureForce): the mean over one step's substeps.
struct ColliderForce {
    std::uint32_t collider = 0; ///< index in the scene's colliders
    glm::vec3 force{0.0f};      ///< [N]
    glm::vec3 torque{0.0f};     ///< about the collider's origin (its pose's translation) [N m]
};

/// The measured colliders' forces as a completed step left them (Simulation::latestForces).
struct ForcesReading {
    std::uint64_t step = 0;               ///< the step they are from (Simulation::steps() after it)
    double time = 0.0;                    ///< simulated time after that step [s]
    std::vector<ColliderForce> colliders; ///< one per measured collider, in collider order
};

/// What Simulation::advance did with one frame's time.
struct FrameAdvance {
    std::uint32_t steps = 0; ///< whole steps taken
    /// Time carried into the next frame [s], in [0, timeStep): the state shown is this far
    /// behind the frame's clock.
    double remainder = 0.0;
    double alpha = 0.0;   ///< remainder / timeStep, in [0, 1): for interpolating a drawn pose
    double dropped = 0.0; ///< time thrown away because the frame owed more than maxSteps [s]
};

/// GPU time per pass group of the latest step whose timer queries are complete [ms];
/// negative where no figure is available yet.
using PassTimes = std::array<double, std::size_t(Pass::Count)>;

/// Reads every collider asset the scene names (readAsset, checks dims and finiteness); a scene
/// built in code is completed first (format::completeScene), its errors returned. Errors
/// name the scene file, the collider index and the asset ("re-bake with sluice-bake").
Result<std::vector<format::ColliderAsset>> loadSceneColliders(const format::Scene& scene);

/// Position Based Fluids on the GPU. Needs a current GL 4.5 context for its whole life.
class Simulation {
public:
    /// Completes the scene (format::completeScene: a scene built in code gets the reader's
    /// defaults and checks, and its errors are returned), compiles the passes, fills the blocks
    /// and uploads the colliders (one per scene collider, in order). Fails with GpuOutOfMemory
    /// when the buffers would not fit, InvalidArgument when the colliders do not match the scene.
    static Result<Simulation> create(const format::Scene& scene,
                                     std::vector<format::ColliderAsset> colliders,
                                     const SimulationOptions& options = {});

    Simulation(Simulation&&) noexcept;
    Simulation& operator=(Simulation&&) noexcept;
    ~Simulation();

    /// One step: timeStep seconds in `substeps` substeps. Queues GPU work only.
    void step();

    /// @name Driving from a game loop (docs/embedding.md)
    /// Calls an engine makes between steps. Each validates what it is given and, on failure,
    /// returns an error with nothing changed.
    /// @{

    /// Steps as many whole steps as `frameSeconds` [s] and the time carried from earlier frames
    /// hold, at most `maxSteps` (the rest is dropped, so a slow frame cannot snowball), and
    /// carries the remainder. InvalidArgument for a negative or non-finite frame time or
    /// maxSteps 0.
    Result<FrameAdvance> advance(double frameSeconds, std::uint32_t maxSteps = 4);

    /// Places a static or kinematic collider, or a dynamic body the game holds
    /// (setBodyKinematic), from the next step on: over that step it moves from where it is now
    /// to `translation` [m] and `rotation` (asset frame -> world; normalised here), linear in
    /// translation and slerped in rotation across the substeps, so friction and the push-out see
    /// its velocity; then it stays there until the next call. Its scene motion (velocities,
    /// keyframes) no longer applies. InvalidArgument for an index out of range, a dynamic body
    /// the game does not hold or a zero quaternion; NonFinite for a non-finite number.
    Result<void> setColliderPose(std::uint32_t collider, glm::vec3 translation, glm::quat rotation);

    /// Moves dynamic body `collider` at once, without sweeping through what lies between (a
    /// respawn, a checkpoint): from the next step its asset frame is at `translation` [m] and
    /// `rotation` (normalised here), moving at `linearVelocity` [m/s] (of its centre of mass) and
    /// `angularVelocity` [rad/s, world]; the water and contacts take it from there. A body the
    /// game holds (setBodyKinematic) is placed there without motion and stays; the velocities
    /// are then unused (its poses give it its velocity). InvalidArgument for an index out of range,
    /// a collider that is no dynamic body or a zero quaternion; NonFinite for a non-finite number.
    Result<void> teleportBody(std::uint32_t collider, glm::vec3 translation, glm::quat rotation,
                              glm::vec3 linearVelocity = glm::vec3(0.0f),
                              glm::vec3 angularVelocity = glm::vec3(0.0f));

    /// Copies the particles with ids firstId .. firstId + count - 1 into the game's buffers, in
    /// id order (ParticleCopyTarget), on the GPU and without waiting: a draw, copy or compute
    /// pass the game issues after it in this context reads the result. It changes the GL state
    /// a step changes (docs/embedding.md). InvalidArgument, with nothing written, for a name
    /// that is no buffer or a buffer smaller than count * 16 bytes; a GL error if its pass
    /// cannot be built (on first use).
    Result<void> copyParticlesById(const ParticleCopyTarget& target);

    /// Hands dynamic body `collider` to the game (`kinematic` true) or back to the water
    /// (false), from the next step. While kinematic it goes only where setColliderPose puts it
    /// (reaching each pose at the end of the next step, across its substeps, as a kinematic
    /// collider does) and otherwise stays still: gravity, the water and the contacts do not move
    /// it, the water still feels it and its force and torque are still reported (bodies,
    /// latestBodies), and a body it meets takes the whole correction. Handed back, it keeps the
    /// velocity its last step's motion gave it (teleportBody gives it another). Taking a body
    /// waits for the GPU once, to read where it is; giving it back does not wait. Either is a
    /// no-op when the body already is so. InvalidArgument for an index out of range or a
    /// collider that is no dynamic body.
    Result<void> setBodyKinematic(std::uint32_t collider, bool kinematic);

    /// Adds particles at `positions` [m] with `velocities` [m/s] (empty: at rest; else one per
    /// position), uploading only them, and returns the first new id: they get first, first + 1,
    /// ... in order, and every other particle keeps its id. They join from the next step.
    /// InvalidArgument when they do not fit the capacity or the velocities do not match;
    /// NonFinite for a non-finite number.
    Result<std::uint32_t> addParticles(const std::vector<glm::vec3>& positions,
                                       const std::vector<glm::vec3>& velocities = {});

    /// Removes the particles with these ids at the next step (docs/embedding.md, "Removing
    /// particles"); an id already removed is ignored. InvalidArgument for an id never given out,
    /// GpuOutOfMemory if the list's buffer cannot grow; nothing changed on failure.
    Result<void> removeParticles(const std::vector<std::uint32_t>& ids);

    /// Removes the particles whose position lies in [min, max) at the next step. InvalidArgument
    /// for a box with max <= min on an axis or with the drains already kMaxDrains boxes;
    /// NonFinite for a corner that is not finite.
    Result<void> removeParticlesIn(glm::vec3 min, glm::vec3 max);

    /// Replaces the drains (the scene's "drains"): boxes that remove every particle that enters
    /// them, from the next step on. Errors as removeParticlesIn's, for each box.
    Result<void> setDrains(const std::vector<format::Drain>& drains);

    /// The drains now.
    const std::vector<format::Drain>& drains() const;

    /// The particle buffers now (after the last step or addParticles).
    ParticleView particleView() const;

    /// Every dynamic body (forces, torques, poses) as the newest step whose results the GPU has
    /// finished left it, without waiting: each step queues a copy of the bodies' records and a
    /// fence, and this returns the newest copy whose fence has passed, typically a step or two
    /// behind. Empty until one has (and always in a scene without bodies).
    std::optional<BodiesReading> latestBodies() const;

    /// Starts (or stops) measuring the fluid's force and torque on a static or kinematic
    /// collider (the scene's "measureForce"): from the next step, every push it gives a particle
    /// is summed, as a dynamic body's reaction is (docs/embedding.md, "Forces on colliders").
    /// InvalidArgument for an index out of range or a dynamic body (its force is in
    /// latestBodies); a GL error if the pass cannot be built.
    Result<void> measureForce(std::uint32_t collider, bool on);

    /// The measured colliders' forces as the newest step the GPU has finished left them, without
    /// waiting (a copy and a fence per step, as latestBodies). Empty until one has, and while no
    /// collider is measured.
    std::optional<ForcesReading> latestForces() const;

    /// @}

    /// Statistics of the latest step (waits for the GPU; one small readback).
    StepStats readStats();

    /// GPU time per pass of the latest step with complete timer queries; never waits.
    PassTimes passTimes();

    /// Waits for every timer query in flight, then returns the GPU time per pass summed over
    /// everything since the previous call [ms] (for benchmarks: call it after each step).
    PassTimes drainPassTimes();

    /// Current particles, in memory order (ids identify them), without the removed ones. Waits
    /// for the GPU.
    std::vector<ParticleState> downloadParticles() const;

    /// Changes the simulation parameters from the next step on (the viewer's live panel).
    /// `spacing`, `restDensity` and `capacity` keep their values: they fix the particle mass and
    /// size the buffers. Fails, with nothing changed, for values the scene reader would reject:
    /// NonFinite for a non-finite number; InvalidArgument for kernelRadius outside
    /// [1.5 spacing, 4 spacing], a timeStep <= 0, zero substeps or iterations, minIterations >
    /// maxIterations, scorrDeltaQ outside [0, kernelRadius), a negative targetDensityError,
    /// relaxation, scorrK, xsph or vorticity, or scorrN < 1, or a kernelRadius whose reach a
    /// sparse dynamic body's band does not hold (checkColliderBands, as when the scene was
    /// loaded: the message names the `--band` to re-bake with). A larger maxIterations grows two
    /// small GPU buffers; if that allocation fails, its error is returned (GpuOutOfMemory).
    Result<void> setParameters(const format::SimulationParams& params);

    /// Current parameters (the scene's, or the last setParameters).
    const format::SimulationParams& parameters() const;

    /// Turns every emitter on or off. Off: no new particles, and the layers due meanwhile are
    /// skipped, so switching on starts a nozzle where its schedule is, without a burst.
    void setEmittersEnabled(bool enabled);
    bool emittersEnabled() const;

    /// Slots in use: the particles live, and for a step or two after a removal the removed
    /// ones not yet compacted away (readStats().particles counts the live ones exactly).
    std::uint32_t particleCount() const;
    /// Particles live after the last step, exactly; they are slots 0 to n - 1 of the buffers
    /// until the next addParticles. Once a particle may have been removed, a 4-byte readback
    /// (waits for the GPU); otherwise particleCount().
    std::uint32_t liveParticleCount() const;
    /// Particles at most.
    std::uint32_t capacity() const;
    /// Simulated time [s] and steps done.
    double time() const;
    std::uint64_t steps() const;

    /// The buffers renderers read: vec4 positions [m] and vec4 velocities [m/s] with the
    /// density error in w, particleCount() of them, valid after step() returns.
    const gpu::Buffer& positionBuffer() const;
    const gpu::Buffer& velocityBuffer() const;

    /// GPU memory the simulation allocated, colliders included [bytes].
    std::uint64_t gpuBytes() const;
    /// Of that, the bytes per particle of capacity [bytes]: the particle arrays (7 vec4 and 5
    /// uint, 132) and the neighbour mask (48), plus the hash table (8 bytes x max(1024,
    /// bit_ceil(2 capacity)) buckets, and 4) divided by the capacity, rounded up: 196 to 212
    /// from 512 particles up (the table has at least 1024 buckets). Colliders, statistics and
    /// parameters are not included.
    std::uint64_t bytesPerParticle() const;

    /// Dispatches and memory barriers queued so far, every step's (the substeps' and the step
    /// statistics'); counted on the CPU where each is issued, so an indirect solve dispatch the
    /// early stop left idle counts too (StepStats::solveDispatches says which ran).
    GpuCommandCount commandCount() const;
    /// Invocations per particle of the neighbour passes (SimulationOptions::neighbourLanes).
    std::uint32_t neighbourLanes() const;
    /// Whether the neighbour passes fetch other particles' data through texel views (false:
    /// from storage blocks; SimulationOptions::neighboursFromStorage).
    bool neighbourTexels() const;

    /// The neighbour grid of the next step: with a domain box whose h-wide cells are no more
    /// than the hash table's buckets, a dense grid of that many cells per axis (no hash
    /// collisions, three cells of a row in one range); otherwise (0, 0, 0): the hash. Follows
    /// kernelRadius changes made through setParameters.
    glm::uvec3 neighbourGridCells() const;

    /// Every dynamic body after the latest step, in scene order (one small readback; waits for
    /// the GPU). Empty when the scene has none.
    std::vector<BodyState> bodies() const;

    /// Each scene collider's pose now: kinematic ones from the scene, dynamic ones from the GPU
    /// (one small readback when there are bodies).
    std::vector<ColliderPose> colliderPoses() const;

    /// Pulls a body with the mouse spring from the next step on; nullopt lets go. Fails with
    /// InvalidArgument for a body index out of range, NonFinite for a non-finite point.
    Result<void> setDrag(const std::optional<BodyDrag>& drag);

    /// The nearest dynamic body the ray from `origin` along `direction` (need not be unit)
    /// meets, by sphere tracing each body's field at its current pose on the CPU; nullopt when
    /// it meets none. Reads the bodies back (a sync).
    std::optional<BodyHit> pickBody(glm::vec3 origin, glm::vec3 direction) const;

    /// The boundary volume the domain's walls and the static and kinematic colliders add to a
    /// particle's density at each world point [m], as the lambda pass adds it: per point, w is
    /// the share (of rho / rho0) and xyz its gradient [1/m]. The colliders at their pose of the
    /// last substep. Colliders with a volume map (docs/pbf.md, "Volume maps") include it. One
    /// small dispatch and readback (a sync).
    Result<std::vector<glm::vec4>> solidBoundaryAt(const std::vector<glm::vec3>& points);

    /// Static and kinematic colliders with a volume map (baked with the collider or built when
    /// the scene starts, and rebuilt when kernelRadius changes).
    std::uint32_t volumeMapCount() const;

    /// How the volume maps were last made: taken from the colliders' assets (baked for this
    /// kernel radius: `sluice-bake bake --volume-map`), or built on the GPU, and at load how
    /// long building them took.
    VolumeMapLoad volumeMapLoad() const;

    /// Particles of the fluid blocks left out at the start because their centre was inside a
    /// dynamic body.
    std::uint32_t particlesRemovedAtSpawn() const;

    /// Constants derived from the scene's parameters.
    const PbfConstants& constants() const;
    const format::Scene& scene() const;

    /// @name For tests only
    /// Hooks for the test suites to set up and inspect the solver's internal state; the
    /// runtime and its programs do not call them, and they may change with the solver.
    /// @{

    /// Replaces every particle with a hand-made state. Fails with InvalidArgument when there
    /// are more than capacity() of them.
    Result<void> setParticles(const std::vector<ParticleState>& particles);

    /// Work groups that each solver iteration's lambda and delta dispatches launched in the
    /// last substep, maxIterations of them: 0 for the iterations after the early stop, which
    /// the GPU skips without the CPU knowing where it stopped. Reads the GPU back (a sync), so
    /// between steps only.
    std::vector<std::uint32_t> solveGroups() const;

    /// The buffers of the last substep that fix N(i) (docs/pbf.md step 3), read back for the
    /// tests' decoder of the neighbour mask: per particle in sorted order its x* at the substep
    /// start and its id, the buckets' ranges (cellStart, one more than the buckets) and the
    /// masks (kNeighbourMaskWords each), and the grid they were built on. A sync.
    struct NeighbourState {
        std::vector<glm::vec4> start; ///< x* at the substep start (xyz) [m]
        std::vector<std::uint32_t> ids;
        std::vector<std::uint32_t> cellStart;
        std::vector<std::uint32_t> mask;
        glm::uvec3 gridDims{0};      ///< dense grid cells per axis; 0: the hash
        glm::vec3 gridOrigin{0.0f};  ///< the dense grid's corner [m]
        float h = 0.0f;              ///< cell size [m]
        std::uint32_t tableSize = 0; ///< hash buckets (a power of two)
    };
    NeighbourState neighbourState() const;

    /// @}

private:
    struct Impl;
    explicit Simulation(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

} // namespace sluice::rt
