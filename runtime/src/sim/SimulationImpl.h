// Private: the state of a Simulation (Simulation::Impl, made of the groups in their own headers)
// and the small helpers its sources share: Simulation.cpp (creation, parameters),
// SimulationBuffers.cpp (buffers, uploads, programs), SimulationPasses.cpp (the step, pass by
// pass) and SimulationReadback.cpp (what comes back).
#pragma once

#include "sluice/rt/sim/Simulation.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <span>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "bodies/BodyBuffers.h"
#include "colliders/ColliderBands.h"
#include "colliders/ColliderState.h"
#include "grid/NeighbourGrid.h"
#include "render/GlObjects.h"
#include "shared/Bodies.h"
#include "shared/ChunkedDispatch.h"
#include "shared/Pbf.h"
#include "sim/ParticleBuffers.h"
#include "sim/ParticleRemoval.h"
#include "sim/StepStatistics.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/gpu/BufferTexture.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/gpu/Program.h"
#include "sluice/gpu/colliders/ColliderRecord.h"
#include "sluice/gpu/colliders/SparseGrids.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {

using gpu::bindColliderRecords;
using gpu::colliderRecord;
using gpu::kColliderRecordBytes;
using gpu::alignToGrid;
using gpu::sparseSlotBytes;

static_assert(shared::kMaxBodies == format::kMaxSceneColliders,
              "one body pass holds every dynamic body a scene may have");
static_assert(shared::kMaxColliders == format::kMaxSceneColliders,
              "the colliders' uniform block holds every collider a scene may have");

inline constexpr std::uint64_t kMaxGroupsPerDispatch = shared::kPbfMaxGroupsPerDispatch;
inline constexpr std::uint32_t kNoStop = shared::kPbfNoStop;
inline constexpr std::size_t kStatsHeaderBytes = sizeof(shared::PbfStats);

inline std::uint32_t groupsFor(std::uint32_t items) {
    return gpu::groupCount(items, shared::kPbfLocalSize);
}

// Affine world transform of a pose: translate * rotate * scale.
inline glm::mat4 poseMatrix(const ColliderPose& pose) {
    return glm::translate(glm::mat4(1.0f), pose.translation) * glm::mat4_cast(pose.rotation) *
           glm::scale(glm::mat4(1.0f), glm::vec3(pose.scale));
}

// The dense grids' part of the SDF buffer, rounded up so the sparse grids after it start aligned.
inline std::uint64_t denseBytes(const std::vector<format::ColliderAsset>& assets) {
    std::uint64_t floats = 0;
    for (const format::ColliderAsset& a : assets)
        floats += a.sparse() ? 0 : a.pointCount();
    return alignToGrid(floats * sizeof(float));
}

// The whole SDF buffer [bytes]: dense grids, then sparse grids.
inline std::uint64_t colliderDataBytes(const std::vector<format::ColliderAsset>& assets) {
    std::uint64_t bytes = denseBytes(assets);
    for (const format::ColliderAsset& a : assets)
        bytes += a.sparse() ? sparseSlotBytes(a) : 0;
    return bytes;
}

inline bool anySparse(const std::vector<format::ColliderAsset>& assets) {
    return std::any_of(assets.begin(), assets.end(),
                       [](const format::ColliderAsset& a) { return a.sparse(); });
}

// Whether the current context renders in software (Mesa's llvmpipe or softpipe, SwiftShader),
// which runs a work group's invocations in turn on one CPU thread: there, lanes that split one
// item's work only add their barriers.
inline bool softwareRenderer() {
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const std::string_view name = renderer ? renderer : "";
    for (std::string_view software : {"llvmpipe", "softpipe", "SwiftShader"})
        if (name.find(software) != std::string_view::npos)
            return true;
    return false;
}

// Invocations of a body's work group in the body pass for the current context.
inline std::uint32_t bodyGroupSize() {
    return softwareRenderer() ? shared::kBodyLanesSoftware : shared::kBodyLanes;
}

// Invocations per particle of the neighbour passes for `capacity` particles on this context.
inline std::uint32_t neighbourLanesFor(std::uint32_t capacity) {
    if (softwareRenderer())
        return 1;
    std::uint32_t lanes = 1;
    while (lanes < 8 && std::uint64_t(capacity) * lanes * 2 <= kNeighbourLanesTarget)
        lanes *= 2;
    return lanes;
}

// A Simulation's state, grouped by concept, each group with its own header: the particles, the
// neighbour grid, the colliders, the bodies, the statistics and the removal; what is left here
// is the scene, the derived constants, the programs of the passes and the clock. The methods,
// which work across the groups, are defined by topic in Simulation.cpp, SimulationBuffers.cpp,
// SimulationPasses.cpp, SimulationControl.cpp, SimulationReadback.cpp and
// colliders/VolumeMaps.cpp.
struct Simulation::Impl : ParticleBuffers,
                          NeighbourGrid,
                          ColliderState,
                          BodyBuffers,
                          StepStatistics,
                          ParticleRemoval {
    format::Scene scene;
    PbfConstants k;
    SimulationOptions options;
    std::uint32_t maxIterations = 0;
    double time = 0.0;
    std::uint64_t steps = 0;
    std::uint64_t gpuBytes = 0;
    std::uint64_t bytesPerParticle = 0;
    std::uint32_t substepInStep = 0; // which substep of the step is running
    double carried = 0.0;            // the frame time advance() has not stepped yet [s]

    gpu::Program predict, scatter, bucketSort, reorder, scatterReorder, lambda, delta, vorticity,
        confine, stats, bodies;
    gpu::Buffer params;    // the parameter block (PbfParams)
    gpu::Buffer solveArgs; // PbfDispatchArgs[maxIterations * solveChunks], see Pbf.h
    std::uint32_t solveChunks = 1;
    std::optional<shared::PbfParams> uploadedParams; // what the parameter block holds

    explicit Impl(const format::Scene& s)
        : ParticleBuffers(s), ColliderState(s.colliders.size()), ParticleRemoval(s), scene(s) {}

    /// Where static or kinematic collider c is at time t [s]: its set pose, else its scene motion.
    ColliderPose poseOf(std::size_t c, float t) const {
        if (const std::optional<DrivenPose>& d = driven[c])
            return interpolatePose(d->from, d->t0, d->to, d->t1, t);
        return colliderPose(scene.colliders[c], t);
    }

    /// Sizes that follow from the scene and the options: capacity, iteration cap, hash table,
    /// neighbour lanes, solve chunks. InvalidArgument when the passes would be too large.
    Result<void> size(const SimulationOptions& options);
    /// A GPU buffer of the solver and its size [bytes].
    struct BufferSpec {
        gpu::Buffer* buffer;
        std::uint64_t bytes;
        const char* label;
    };
    /// Every buffer allocate() creates, with the SDF buffer's size `sdfBytes`.
    std::vector<BufferSpec> bufferSpecs(std::uint64_t sdfBytes);
    Result<void> allocate();
    /// The SDF buffer's texel view, where sdfAsTexels (allocate ends with it).
    Result<void> viewSdfAsTexels();
    /// The neighbour passes' texel views, where neighboursAsTexels (allocate ends with them).
    Result<void> viewNeighboursAsTexels();
    /// Binds the views a neighbour pass fetches through: the solve's x* (`positions`), or
    /// vorticity and confinement's x, v and omega; the start positions, masks and cell ranges
    /// always. Nothing where neighboursAsTexels is false.
    void bindNeighbourTexels(const gpu::BufferTexture& positions,
                             const gpu::BufferTexture* velocities = nullptr,
                             const gpu::BufferTexture* omega = nullptr) const;
    Result<void> compilePasses();
    /// Every collider grid into the SDF buffer (dense ones first, then the sparse ones,
    /// 32-byte aligned), their records, and the bodies' initial records and contact points.
    void uploadColliderGrids();
    /// The fluid blocks' particles, less those inside a body. InvalidArgument when they
    /// outnumber the capacity.
    Result<void> fillBlocks();
    void uploadParams();
    /// Whether collider c is one to map: static or kinematic, its map at most
    /// kVolumeMapMaxPoints points (VolumeMaps.cpp).
    bool mapsCollider(std::size_t c) const;
    /// Whether collider c gets a volume map: mapsCollider, and every map fitting in the SDF
    /// buffer's storage block with the grids (volumeMapsFit).
    bool wantsVolumeMap(std::size_t c) const;
    /// Points of collider c's volume map: one per grid point of a dense grid, 512 per leaf of a
    /// sparse one (its band's voxels, stored per leaf).
    std::uint64_t volumeMapPoints(std::size_t c) const;
    /// Words of the volume maps of the colliders to map, after every grid in the SDF buffer.
    std::uint64_t volumeMapWords() const;
    /// The SDF buffer's size [bytes]: every grid, then the volume maps if they fit in a storage
    /// block of `maxBlockBytes` (and 4 GiB) with them; sets volumeMapsFit.
    std::uint64_t sdfBufferBytes(std::int64_t maxBlockBytes);
    /// Every volume map for the current h: baked with the collider where its asset has one for
    /// this support, else computed (pbf_volume_map.comp). Sets volumeMapLoad (but its time).
    Result<void> buildVolumeMaps();
    /// Collider c's kernel radius in its asset's units: h over its placement scale.
    double supportOf(std::size_t c) const;
    /// The step's compile defines: the sparse reader when a collider is sparse, and
    /// SLUICE_SDF_STORAGE when the dense samples are read from storage (sdfAsTexels false).
    std::vector<gpu::ShaderDefine> colliderDefines() const;
    /// Binds what the passes read of the colliders: the records (ColliderRecord.h), the SDF
    /// buffer and its texel view.
    void bindColliders() const;
    void uploadColliders(double t0, double t1);
    /// The body of dynamic collider `collider`, for `call`'s messages; else InvalidArgument
    /// ending with `otherwise`, what to do instead.
    Result<std::uint32_t> bodyOf(const std::string& call, std::uint32_t collider,
                                 const char* otherwise) const;
    /// Body b's record from its set-up, its asset frame at `pose`, at rest; with the game's
    /// zero inverse mass and inertia while it holds the body.
    shared::GpuBody placedBody(std::uint32_t b, const ColliderPose& pose) const;
    /// At a step's start: each body the game holds, at its pose, moving at the velocities that
    /// take it to the pose setColliderPose set by the step's end (at rest without one).
    void moveKinematicBodies();
    void append(const std::vector<ParticleState>& particles);
    /// The view's draw command: the live particles, which lead the slots. After a sort that had
    /// removed particles, their count as the sort left it (a GPU copy); else `count`.
    void updateDrawArgs();
    /// The snapshot buffers of latestBodies (when there are bodies).
    Result<void> allocateBodySnapshots();
    /// Queues the copy of the bodies' records after a step, and its fence.
    void snapshotBodies();
    /// The removal id list's buffer, for `ids` ids (grown, never shrunk), and the live-count
    /// records. GpuOutOfMemory when it cannot grow.
    Result<void> allocateRemoval(std::size_t ids);
    /// After a step: drops the removed particles a completed live-count copy reports from the
    /// count (they are the last slots), then queues this step's copy.
    void trimRemoved();
    /// The live count after the last step: the count where no particle was removed, else a
    /// readback (a sync).
    std::uint32_t liveNow() const;
    /// BodyState of each GpuBody record.
    std::vector<BodyState> bodyStates(const std::vector<shared::GpuBody>& records) const;
    /// One substep: the passes below, in the order of docs/pbf.md.
    void substep();
    void emit(double t0, double t1);
    void bindSharedBuffers() const;
    void predictPositions();
    void sortIntoBuckets();
    void solve();
    void applyVorticityAndXsph();
    void integrateBodies();
    void measureColliderForces();
    void bindParticles(const gpu::Buffer& posIn, const gpu::Buffer& velIn) const;
    void memoryBarrier(GLbitfield bits) {
        glMemoryBarrier(bits);
        ++commands.barriers;
    }
    /// The barrier between two passes: storage writes visible to the next pass's storage reads
    /// and, where the neighbour passes fetch texels, to its fetches.
    void barrier() { memoryBarrier(passBarrierBits()); }
    GLbitfield passBarrierBits() const {
        return GL_SHADER_STORAGE_BARRIER_BIT |
               (neighboursAsTexels ? GL_TEXTURE_FETCH_BARRIER_BIT : GLbitfield(0));
    }
    /// Sets `bytes` of the statistics buffer from byte `offset` on to the uint `value`, on the
    /// GPU (offsets from offsetof(shared::PbfStats, ...)).
    void fillStats(std::size_t offset, std::size_t bytes, std::uint32_t value) const {
        glClearNamedBufferSubData(statsBuf.id(), GL_R32UI, GLintptr(offset), GLsizeiptr(bytes),
                                  GL_RED_INTEGER, GL_UNSIGNED_INT, &value);
    }
    void dispatch(const gpu::Program& program, std::uint32_t items) {
        commands.dispatches +=
            program.dispatchChunked(glm::uvec3(groupsFor(items), 1, 1), kMaxGroupsPerDispatch);
    }
    std::uint64_t solveArgsBytes(std::uint32_t iterations) const {
        return std::uint64_t(iterations) * solveChunks * sizeof(shared::PbfDispatchArgs);
    }
    void dispatchSolve(const gpu::Program& program, std::uint32_t iteration);
    /// Resets what the predict pass resets (the stop and the error sums) when no particle is
    /// live and it does not run.
    void openEmptySubstep() const;
    /// Cells per axis of the dense grid over the domain box at the current h, or 0 when the
    /// hash is used (no domain, or more cells than the hash table's buckets).
    glm::uvec3 denseGridDims() const;
    /// Buckets in use: the dense grid's cells, or tableSize for the hash.
    std::uint32_t activeBuckets() const {
        const glm::uvec3 dims = denseGridDims();
        return dims.x > 0 ? dims.x * dims.y * dims.z : tableSize;
    }
    void begin(Pass p) {
        if (options.timers)
            timers[std::size_t(p)].begin();
    }
    void end(Pass p) {
        if (options.timers)
            timers[std::size_t(p)].end();
    }
};

} // namespace sluice::rt
