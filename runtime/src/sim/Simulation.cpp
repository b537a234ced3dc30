// The GPU step of docs/pbf.md: buffers, the counting-sort neighbour grid and the solver passes.
#include "sluice/rt/Simulation.h"

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

#include "BodySetup.h"
#include "ColliderBands.h"
#include "PrefixScan.h"
#include "SparseGrids.h"
#include "shared/Bodies.h"
#include "shared/ChunkedDispatch.h"
#include "shared/Pbf.h"
#include "sluice/format/AssetIO.h"
#include "sluice/format/SdfSampler.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/gpu/Program.h"
#include "sluice/rt/ColliderRecord.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {

namespace {

constexpr std::uint64_t kMaxGroupsPerDispatch = shared::kPbfMaxGroupsPerDispatch;
constexpr std::uint32_t kNoStop = shared::kPbfNoStop;
constexpr std::size_t kStatsHeaderBytes = sizeof(shared::PbfStats);

std::uint32_t groupsFor(std::uint32_t items) {
    return gpu::groupCount(items, shared::kPbfLocalSize);
}

// Affine world transform of a pose: translate * rotate * scale.
glm::mat4 poseMatrix(const ColliderPose& pose) {
    return glm::translate(glm::mat4(1.0f), pose.translation) * glm::mat4_cast(pose.rotation) *
           glm::scale(glm::mat4(1.0f), glm::vec3(pose.scale));
}

// The dense grids' part of the SDF buffer, rounded up so the sparse grids after it start aligned.
std::uint64_t denseBytes(const std::vector<format::ColliderAsset>& assets) {
    std::uint64_t floats = 0;
    for (const format::ColliderAsset& a : assets)
        floats += a.sparse() ? 0 : a.pointCount();
    return alignToGrid(floats * sizeof(float));
}

// The whole SDF buffer [bytes]: dense grids, then sparse grids.
std::uint64_t colliderDataBytes(const std::vector<format::ColliderAsset>& assets) {
    std::uint64_t bytes = denseBytes(assets);
    for (const format::ColliderAsset& a : assets)
        bytes += a.sparse() ? sparseSlotBytes(a) : 0;
    return bytes;
}

bool anySparse(const std::vector<format::ColliderAsset>& assets) {
    return std::any_of(assets.begin(), assets.end(),
                       [](const format::ColliderAsset& a) { return a.sparse(); });
}

// Whether the current context renders in software (Mesa's llvmpipe or softpipe, SwiftShader),
// which runs a work group's invocations in turn on one CPU thread: there, lanes that split one
// item's work only add their barriers.
bool softwareRenderer() {
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const std::string_view name = renderer ? renderer : "";
    for (std::string_view software : {"llvmpipe", "softpipe", "SwiftShader"})
        if (name.find(software) != std::string_view::npos)
            return true;
    return false;
}

// Invocations of the body pass's work group for the current context.
std::uint32_t bodyGroupSize() {
    return softwareRenderer() ? shared::kBodyLocalSize : shared::kBodyGroupSize;
}

// Invocations per particle of the neighbour passes for `capacity` particles on this context.
std::uint32_t neighbourLanesFor(std::uint32_t capacity) {
    if (softwareRenderer())
        return 1;
    std::uint32_t lanes = 1;
    while (lanes < 8 && std::uint64_t(capacity) * lanes * 2 <= kNeighbourLanesTarget)
        lanes *= 2;
    return lanes;
}

} // namespace

const char* passName(Pass pass) {
    switch (pass) {
    case Pass::Emit: return "emit";
    case Pass::Predict: return "predict";
    case Pass::Sort: return "sort";
    case Pass::Solve: return "solve";
    case Pass::Velocity: return "velocity";
    case Pass::Vorticity: return "vorticity+xsph";
    case Pass::Bodies: return "bodies";
    case Pass::Stats: return "stats";
    case Pass::Count: break;
    }
    return "?";
}

Result<std::vector<format::ColliderAsset>> loadSceneColliders(const format::Scene& scene) {
    std::vector<format::ColliderAsset> assets;
    for (std::size_t c = 0; c < scene.colliders.size(); ++c) {
        const format::SceneCollider& collider = scene.colliders[c];
        const std::string path =
            collider.resolvedPath.empty() ? collider.asset : collider.resolvedPath;
        auto asset = format::readAsset(path);
        if (!asset)
            return fail(asset.error().code, scene.path + ": colliders[" + std::to_string(c) +
                                                "]: " + asset.error().detail);
        assets.push_back(std::move(*asset));
    }
    // Dynamic bodies need a volume and a usable mass, sparse colliders a band as wide as the
    // solver reads: checked here, on the CPU, before any output or GL context exists
    // (Simulation::create sets them up).
    if (auto ok = checkBodies(scene, assets); !ok)
        return ok.error();
    if (auto ok = checkColliderBands(scene, assets); !ok)
        return ok.error();
    return assets;
}

struct Simulation::Impl {
    format::Scene scene;
    PbfConstants k;
    SimulationOptions options;
    std::uint32_t capacity = 0;
    std::uint32_t tableSize = 0;
    std::uint32_t maxIterations = 0;
    std::uint32_t count = 0;
    std::uint32_t nextId = 0;
    int cur = 0; // which of pos/vel/id [2] holds the current particles
    double time = 0.0;
    std::uint64_t steps = 0;
    bool capacityReached = false;
    bool emittersOn = true;
    std::uint64_t gpuBytes = 0;
    std::uint64_t bytesPerParticle = 0;
    EmitterSchedule emitters;
    std::vector<format::ColliderAsset> colliderAssets;
    std::vector<shared::GpuCollider> colliderRecords;
    BodySetup bodySetup;
    std::uint32_t bodyCount = 0;
    std::uint32_t removedAtSpawn = 0; // particles of the blocks that started inside a body
    std::optional<BodyDrag> drag;      // the viewer's mouse spring
    std::uint32_t substepInStep = 0;   // which substep of the step is running
    std::uint32_t lanes = 1;           // invocations per particle of the neighbour passes

    gpu::Program predict, scatter, bucketSort, reorder, scatterReorder, lambda, delta, velocity,
        vorticity, confine, stats, bodies;
    std::unique_ptr<PrefixScan> scan;
    gpu::Buffer pos[2], vel[2], id[2], pred[2], predStart;
    gpu::Buffer cellCount, cellStart, hash, rank, sortedToOld, statsBuf;
    gpu::Buffer neighbourMask; // uint[kNeighbourMaskWords] per particle of capacity
    gpu::Buffer colliderBuf, sdfBuf, params;
    gpu::Buffer bodyBuf, bodySums, bodySamples; // GpuBody[], fixed-point sums, contact points
    gpu::Buffer solveArgs; // PbfDispatchArgs[maxIterations * solveChunks], see Pbf.h
    std::uint32_t solveChunks = 1;
    std::optional<shared::PbfParams> uploadedParams; // what the parameter block holds
    GpuCommandCount commands; // queued by the substeps and the step statistics, all steps
    std::vector<gpu::GpuTimer> timers;
    std::array<std::uint64_t, std::size_t(Pass::Count)> drainedNs{}; // totals at the last drain
    std::vector<ParticleState> staging;

    explicit Impl(const format::Scene& s) : scene(s), emitters(s) {}

    Result<void> allocate();
    Result<void> compilePasses();
    void uploadParams();
    void uploadColliders(double t0, double t1);
    void append(const std::vector<ParticleState>& particles);
    /// One substep: the passes below, in the order of docs/pbf.md.
    void substep();
    void emit(double t0, double t1);
    void bindSharedBuffers() const;
    void predictPositions();
    void sortIntoBuckets();
    void solve();
    void updateVelocities();
    void applyVorticityAndXsph();
    void integrateBodies();
    void bindParticles(const gpu::Buffer& posIn, const gpu::Buffer& velIn) const;
    void memoryBarrier(GLbitfield bits) {
        glMemoryBarrier(bits);
        ++commands.barriers;
    }
    void barrier() { memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT); }
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

Result<void> Simulation::Impl::allocate() {
    struct Alloc {
        gpu::Buffer* buffer;
        std::uint64_t bytes;
        const char* label;
    };
    const std::uint64_t n = capacity;
    const std::uint64_t v4 = 16, u = 4;
    const std::uint64_t sdfBytes = colliderDataBytes(colliderAssets);
    if (sdfBytes > 0xffffffffull) // GpuCollider::sdfOffset and PNanoVDB's addresses: 32 bits
        return fail(ErrorCode::GpuOutOfMemory,
                    scene.path + ": the colliders' grids take " + std::to_string(sdfBytes) +
                        " bytes, more than the 4 GiB the solver can address; coarsen them or "
                        "bake the large ones with `sluice-bake bake --sparse`");
    const std::vector<Alloc> allocs = {
        {&pos[0], n * v4, "pos 0"},       {&pos[1], n * v4, "pos 1"},
        {&vel[0], n * v4, "vel 0"},       {&vel[1], n * v4, "vel 1"},
        {&pred[0], n * v4, "pred 0"},     {&pred[1], n * v4, "pred 1"},
        {&predStart, n * v4, "predStart"},
        {&id[0], n * u, "id 0"},          {&id[1], n * u, "id 1"},
        {&hash, n * u, "hash"},
        {&rank, n * u, "rank"},           {&sortedToOld, n * u, "sortedToOld"},
        {&cellCount, tableSize * u, "cellCount"},
        {&neighbourMask, n * shared::kNeighbourMaskWords * u, "neighbour mask"},
        {&cellStart, (tableSize + 1) * u, "cellStart"},
        {&statsBuf, kStatsHeaderBytes + maxIterations * sizeof(shared::PbfIterationStats),
         "stats"},
        {&colliderBuf, std::max<std::uint64_t>(1, colliderAssets.size()) *
                           sizeof(shared::GpuCollider),
         "colliders"},
        {&sdfBuf, std::max<std::uint64_t>(u, sdfBytes), "sdf"},
        {&params, sizeof(shared::PbfParams), "params"},
        {&bodyBuf, std::max<std::uint64_t>(1, bodySetup.records.size()) * sizeof(shared::GpuBody),
         "bodies"},
        {&bodySums, std::max<std::uint64_t>(1, bodySetup.records.size()) *
                        shared::kBodySumWords * u,
         "body sums"},
        {&bodySamples, std::max<std::uint64_t>(1, bodySetup.samples.size()) * v4,
         "body contact points"},
        {&solveArgs, solveArgsBytes(maxIterations), "solve dispatch args"},
    };
    std::uint64_t total = 0;
    for (const Alloc& a : allocs)
        total += a.bytes;
    gpuBytes = total;
    // Per particle of capacity: the particle arrays (7 vec4, 5 uint; the vorticity omega lives
    // in the idle position buffer, applyVorticityAndXsph), the neighbour mask and the hash
    // table's cellCount + cellStart, spread over the capacity and rounded up.
    bytesPerParticle = 7 * v4 + 5 * u + shared::kNeighbourMaskWords * u +
                       (u * (2 * std::uint64_t(tableSize) + 1) + n - 1) / n;
    GLint64 maxSsbo = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxSsbo);
    for (const Alloc& a : allocs) {
        if (maxSsbo > 0 && a.bytes > std::uint64_t(maxSsbo))
            return fail(ErrorCode::GpuOutOfMemory,
                        scene.path + ": the " + a.label + " buffer needs " +
                            std::to_string(a.bytes) +
                            " bytes, more than this GL allows in one storage block (" +
                            std::to_string(maxSsbo) +
                            "); lower simulation.capacity or coarsen the colliders");
        auto buffer = gpu::Buffer::create(a.bytes, a.label);
        if (!buffer)
            return fail(buffer.error().code, scene.path + ": " + buffer.error().detail);
        *a.buffer = std::move(*buffer);
    }
    return {};
}

// Lambda or delta of one iteration from its indirect args: a dispatch the early stop has
// zeroed launches no work group, so an idle iteration costs only the API call.
void Simulation::Impl::dispatchSolve(const gpu::Program& program, std::uint32_t iteration) {
    program.use();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, solveArgs.id());
    for (std::uint32_t c = 0; c < solveChunks; ++c) {
        program.set(shared::kGroupOffsetUniform,
                    glm::uvec3(std::uint32_t(c * kMaxGroupsPerDispatch), 0, 0));
        glDispatchComputeIndirect(
            GLintptr((std::size_t(iteration) * solveChunks + c) * sizeof(shared::PbfDispatchArgs)));
        ++commands.dispatches;
        ++commands.indirect;
        if (solveChunks > 1)
            glFlush();
    }
}

glm::uvec3 Simulation::Impl::denseGridDims() const {
    if (!scene.domainMin || !scene.domainMax)
        return glm::uvec3(0);
    // A domain 5 h wide in float is 5.0000001 h: that is 5 cells (cellOf clamps into the grid).
    const glm::dvec3 cells = glm::max(
        glm::ceil(glm::dvec3(*scene.domainMax - *scene.domainMin) / double(k.h) - 1e-3), 1.0);
    if (cells.x * cells.y * cells.z > double(tableSize))
        return glm::uvec3(0);
    return glm::uvec3(cells);
}

void Simulation::Impl::uploadParams() {
    const format::SimulationParams& s = scene.simulation;
    shared::PbfParams p{};
    p.h = k.h;
    p.h2 = k.h * k.h;
    p.poly6Coeff = k.poly6;
    p.spikyGradCoeff = k.spikyGrad;
    p.volume = k.volume;
    p.epsilon = k.epsilon;
    p.lambdaRef = k.lambdaRef;
    p.radius = k.radius;
    p.scorrK = s.scorrK;
    p.scorrN = s.scorrN;
    p.invWDeltaQ = k.wDeltaQ > 0.0f ? 1.0f / k.wDeltaQ : 0.0f;
    p.invH = 1.0f / k.h;
    p.dt = k.dt;
    p.invDt = 1.0f / k.dt;
    p.xsph = s.xsph;
    p.vorticity = s.vorticity;
    p.gravity = s.gravity;
    p.targetDensityError = s.targetDensityError;
    if (scene.domainMin && scene.domainMax) {
        p.domainMin = *scene.domainMin + glm::vec3(k.radius);
        p.domainMax = *scene.domainMax - glm::vec3(k.radius);
        p.hasDomain = 1;
    }
    // A dense grid of h-wide cells over the domain box replaces the hash when it needs no more
    // buckets than the hash table holds (docs/performance.md, "Done"): no hash collisions, and
    // the three cells of a row are one contiguous range of sorted particles. h may change
    // between substeps (setParameters), so this is decided here.
    const glm::uvec3 dims = denseGridDims();
    if (dims.x > 0) {
        p.gridDims = dims;
        p.gridOrigin = *scene.domainMin;
        p.denseGrid = 1;
    }
    p.particleCount = count;
    p.hashMask = tableSize - 1;
    p.colliderCount = std::uint32_t(colliderRecords.size());
    p.minIterations = s.minIterations;
    p.solveChunks = solveChunks;
    p.activeBuckets = activeBuckets();
    p.deterministic = options.deterministic ? 1u : 0u;
    p.maxIterations = maxIterations;
    p.bodyCount = bodyCount;
    p.particleMass = k.mass;
    p.boundaryScale = k.boundaryScale;
    p.bodyOffset = k.bodyOffset;
    // Uploaded only when it changed (an emitter added particles, setParameters): a substep
    // queues no buffer update of its own.
    if (uploadedParams && std::memcmp(&*uploadedParams, &p, sizeof(p)) == 0)
        return;
    params.upload(std::span(&p, 1));
    uploadedParams = p;
}

void Simulation::Impl::uploadColliders(double t0, double t1) {
    if (colliderRecords.empty())
        return;
    for (std::size_t c = 0; c < colliderRecords.size(); ++c) {
        // A dynamic body's record is the body pass's to write (pbf_bodies.comp).
        if (colliderRecords[c].body != shared::kNoBody)
            continue;
        const ColliderPose now = colliderPose(scene.colliders[c], float(t1));
        const ColliderPose before = colliderPose(scene.colliders[c], float(t0));
        const glm::mat4 world = poseMatrix(now);
        shared::GpuCollider& r = colliderRecords[c];
        const shared::GpuCollider uploaded = r;
        r.worldToGrid = glm::inverse(world);
        r.rotation = glm::mat4_cast(now.rotation);
        r.motion = poseMatrix(before) * r.worldToGrid;
        r.scale = now.scale;
        // A static collider's record is uploaded once; a kinematic one's when it moved.
        if (std::memcmp(&uploaded, &r, sizeof(r)) != 0)
            colliderBuf.upload(std::span(&r, 1), c * sizeof(shared::GpuCollider));
    }
}

void Simulation::Impl::append(const std::vector<ParticleState>& particles) {
    if (particles.empty())
        return;
    std::vector<glm::vec4> p, v;
    std::vector<std::uint32_t> ids;
    for (const ParticleState& s : particles) {
        p.emplace_back(s.position, 0.0f);
        v.emplace_back(s.velocity, 0.0f);
        ids.push_back(s.id);
    }
    pos[cur].upload(p, std::size_t(count) * sizeof(glm::vec4));
    vel[cur].upload(v, std::size_t(count) * sizeof(glm::vec4));
    id[cur].upload(ids, std::size_t(count) * sizeof(std::uint32_t));
    count += std::uint32_t(particles.size());
}

void Simulation::Impl::bindParticles(const gpu::Buffer& posIn, const gpu::Buffer& velIn) const {
    posIn.bindStorage(shared::kBindPosIn);
    velIn.bindStorage(shared::kBindVelIn);
}

// One substep: the passes of docs/pbf.md, "One substep at time t", in order. The neighbour
// sort (step 3) counts into buckets in the predict pass and sorts after it.
void Simulation::Impl::substep() {
    const double t0 = time;
    const double t1 = time + k.dt;
    emit(t0, t1);
    if (count == 0)
        openEmptySubstep();
    if (count > 0) {
        bindSharedBuffers();
        predictPositions();
        sortIntoBuckets();
        solve();
        updateVelocities();
        applyVorticityAndXsph();
    }
    if (bodyCount > 0) {
        if (count == 0)
            bindSharedBuffers();
        integrateBodies();
    }
    time = t1;
}

// Step 1, and what the substep's passes read that the CPU owns: new particles, the parameters
// and the kinematic colliders' poses, each uploaded only when it changed. The per-substep
// resets are the GPU's: the predict pass opens the solve (its dispatch args, the stop, the
// error sums) and the scan leaves the cell counts at zero for the next substep.
void Simulation::Impl::emit(double t0, double t1) {
    begin(Pass::Emit);
    staging.clear();
    if (emittersOn && !emitters.emit(float(t0), count, capacity, nextId, staging))
        capacityReached = true;
    append(staging);
    uploadParams();
    uploadColliders(t0, t1);
    end(Pass::Emit);
}

void Simulation::Impl::openEmptySubstep() const {
    fillStats(offsetof(shared::PbfStats, stopIteration), sizeof(std::uint32_t), kNoStop);
    fillStats(kStatsHeaderBytes, statsBuf.size() - kStatsHeaderBytes, 0);
}

// The buffers whose binding no pass of the substep changes. No barrier here: the last pass of
// a substep (or the step statistics) ends with a storage barrier, and the CPU's uploads and
// clears are ordered with the dispatches after them by GL itself.
void Simulation::Impl::bindSharedBuffers() const {
    params.bindBase(GL_UNIFORM_BUFFER, shared::kBindParams);
    statsBuf.bindStorage(shared::kBindStats);
    colliderBuf.bindStorage(shared::kBindColliders);
    sdfBuf.bindStorage(shared::kBindSdf);
    cellCount.bindStorage(shared::kBindCellCount);
    cellStart.bindStorage(shared::kBindCellStart);
    hash.bindStorage(shared::kBindHash);
    rank.bindStorage(shared::kBindRank);
    sortedToOld.bindStorage(shared::kBindSortedToOld);
    neighbourMask.bindStorage(shared::kBindNeighbourMask);
    bodyBuf.bindStorage(shared::kBindBodies);
    bodySums.bindStorage(shared::kBindBodySums);
    bodySamples.bindStorage(shared::kBindBodySamples);
    solveArgs.bindStorage(shared::kBindSolveArgs);
}

// Step 2: x* into pred[0], and each particle counted into its bucket; the solve's dispatch
// args written for the indirect dispatches (hence the command barrier).
void Simulation::Impl::predictPositions() {
    begin(Pass::Predict);
    bindParticles(pos[cur], vel[cur]);
    pred[0].bindStorage(shared::kBindPredOut);
    dispatch(predict, count);
    memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    end(Pass::Predict);
}

// Step 3: counting sort by bucket, then every particle reordered into the other buffers (x* of
// the sorted order into predStart). The scan gives each bucket its range, cellStart[b] ..
// cellStart[b + 1], and zeroes the counts for the next substep. Without --deterministic the
// reorder scatters each particle straight to its slot; with it, the slots are listed first
// (scatter), put in source order inside each bucket, then gathered.
void Simulation::Impl::sortIntoBuckets() {
    begin(Pass::Sort);
    const std::uint32_t buckets = activeBuckets();
    commands += scan->exclusive(cellCount, cellStart, ScanInput{buckets + 1, buckets, true});
    cellStart.bindStorage(shared::kBindCellStart);
    cellCount.bindStorage(shared::kBindCellCount);
    if (options.deterministic) {
        dispatch(scatter, count);
        barrier();
        dispatch(bucketSort, buckets);
        barrier();
    }
    const int nxt = 1 - cur;
    pos[cur].bindStorage(shared::kBindPosIn);
    pos[nxt].bindStorage(shared::kBindPosOut);
    vel[cur].bindStorage(shared::kBindVelIn);
    vel[nxt].bindStorage(shared::kBindVelOut);
    pred[0].bindStorage(shared::kBindPredIn);
    predStart.bindStorage(shared::kBindPredOut);
    id[cur].bindStorage(shared::kBindIdIn);
    id[nxt].bindStorage(shared::kBindIdOut);
    dispatch(options.deterministic ? reorder : scatterReorder, count);
    barrier();
    cur = nxt;
    end(Pass::Sort);
}

// Step 4: the solver iterations. Iteration k reads x* from predStart (k = 0) or
// pred[(k - 1) % 2] and writes pred[k % 2]; predStart keeps the substep's start positions,
// which fix the neighbour sets: lambda of iteration 0 searches the candidates in full and
// records N(i) in neighbourMask, which every later neighbour pass of the substep reads (docs/
// pbf.md step 3). The early stop (pbf_delta.comp) zeroes the dispatch args of the
// later iterations: the CPU issues every dispatch without knowing where the GPU stopped.
void Simulation::Impl::solve() {
    begin(Pass::Solve);
    predStart.bindStorage(shared::kBindPredStart);
    bindParticles(pos[cur], vel[cur]);
    const gpu::Buffer* in = &predStart;
    for (std::uint32_t it = 0; it < maxIterations; ++it) {
        in->bindStorage(shared::kBindPredIn);
        lambda.set("iteration", it);
        dispatchSolve(lambda, it);
        barrier();
        pred[it % 2].bindStorage(shared::kBindPredOut);
        delta.set("iteration", it);
        dispatchSolve(delta, it);
        memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
        in = &pred[it % 2];
    }
    end(Pass::Solve);
}

// Step 5: velocity, x <- x*, non-finite guard; velocities go to the other buffer. The shader
// picks, by stats.stopIteration, the buffer the last iteration that ran wrote.
void Simulation::Impl::updateVelocities() {
    begin(Pass::Velocity);
    pred[0].bindStorage(shared::kBindPredIn);
    pred[1].bindStorage(shared::kBindPredOther);
    vel[cur].bindStorage(shared::kBindVelIn);
    vel[1 - cur].bindStorage(shared::kBindVelOut);
    dispatch(velocity, count);
    barrier();
    end(Pass::Velocity);
}

// Step 6: vorticity confinement and XSPH, back into vel[cur]. The vorticity omega goes into
// pos[1 - cur], the positions before this substep's reorder, which nothing reads again: the
// next reorder overwrites them (16 bytes a particle saved).
void Simulation::Impl::applyVorticityAndXsph() {
    begin(Pass::Vorticity);
    const bool withVorticity = scene.simulation.vorticity > 0.0f;
    pos[1 - cur].bindStorage(shared::kBindOmega);
    vel[1 - cur].bindStorage(shared::kBindVelIn);
    if (withVorticity) {
        dispatch(vorticity, count * lanes);
        barrier();
    }
    vel[cur].bindStorage(shared::kBindVelOut);
    confine.set("withVorticity", withVorticity ? 1u : 0u);
    dispatch(confine, count * lanes);
    barrier();
    end(Pass::Vorticity);
}

// Step 7 (docs/bodies.md): the bodies take the fluid's reaction, move, meet each other and the
// walls, and rewrite their collider records; one work group for all of them.
void Simulation::Impl::integrateBodies() {
    begin(Pass::Bodies);
    bodies.set("dragBody", drag ? drag->body : shared::kNoBody);
    bodies.set("dragAnchor", drag ? drag->anchor : glm::vec3(0.0f));
    bodies.set("dragTarget", drag ? drag->target : glm::vec3(0.0f));
    bodies.set("dragOmega", 2.0f * 3.14159265f * 3.0f);
    bodies.set("firstSubstep", substepInStep == 0 ? 1u : 0u);
    bodies.set("substepShare", 1.0f / float(std::max(1u, scene.simulation.substeps)));
    bodies.use();
    glDispatchCompute(1, 1, 1);
    ++commands.dispatches;
    barrier();
    end(Pass::Bodies);
}

// Compiles every pass of the step with the defines this simulation needs.
Result<void> Simulation::Impl::compilePasses() {
    struct Build {
        gpu::Program* program;
        const char* name;
    };
    const Build builds[] = {
        {&predict, "pbf_predict.comp"},   {&scatter, "pbf_scatter.comp"},
        {&bucketSort, "pbf_bucket_sort.comp"}, {&reorder, "pbf_reorder.comp"},
        {&scatterReorder, "pbf_reorder.comp"},
        {&lambda, "pbf_lambda.comp"},     {&delta, "pbf_delta.comp"},
        {&velocity, "pbf_velocity.comp"}, {&vorticity, "pbf_vorticity.comp"},
        {&confine, "pbf_confine.comp"},   {&stats, "pbf_stats.comp"},
        {&bodies, "pbf_bodies.comp"},
    };
    // NanoVDB's reader (shared/NanoVdbGlsl.h) is compiled in only when a collider needs it.
    const std::array<gpu::ShaderDefine, 1> sparseDefine{{{"SLUICE_SPARSE_COLLIDERS", "1"}}};
    const std::span<const gpu::ShaderDefine> defines =
        anySparse(colliderAssets) ? std::span<const gpu::ShaderDefine>(sparseDefine)
                                        : std::span<const gpu::ShaderDefine>();
    // The body pass's work group (pbf_bodies.comp): kBodyGroupSize invocations on a GPU, 64 on
    // a software renderer, which runs a group's invocations in turn on one CPU thread.
    const std::string groupSize = std::to_string(
        options.bodyGroupSize != 0 ? options.bodyGroupSize : bodyGroupSize());
    std::vector<gpu::ShaderDefine> bodyDefines(defines.begin(), defines.end());
    bodyDefines.push_back({"SLUICE_BODY_GROUP_SIZE", groupSize});
    std::vector<gpu::ShaderDefine> scatterDefines(defines.begin(), defines.end());
    scatterDefines.push_back({"PBF_SCATTER_REORDER", "1"});
    // The neighbour passes split each particle over its lanes; predict sizes their dispatches.
    std::vector<gpu::ShaderDefine> laneDefines(defines.begin(), defines.end());
    laneDefines.push_back({"PBF_LANES", std::to_string(lanes)});
    const gpu::Program* const laned[] = {&predict, &lambda, &delta,
                                         &vorticity, &confine};
    for (const Build& b : builds) {
        std::span<const gpu::ShaderDefine> these = defines;
        if (b.program == &bodies)
            these = bodyDefines;
        else if (b.program == &scatterReorder)
            these = scatterDefines;
        else if (std::find(std::begin(laned), std::end(laned), b.program) != std::end(laned))
            these = laneDefines;
        auto program = gpu::Program::compute(b.name, shaders::shaderSource(b.name), these);
        if (!program)
            return program.error();
        *b.program = std::move(*program);
    }
    return {};
}

Result<Simulation> Simulation::create(const format::Scene& scene,
                                      std::vector<format::ColliderAsset> colliders,
                                      const SimulationOptions& options) {
    if (colliders.size() != scene.colliders.size())
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": " + std::to_string(scene.colliders.size()) +
                        " colliders in the scene but " + std::to_string(colliders.size()) +
                        " assets given");
    if (const std::uint32_t l = options.neighbourLanes;
        l != 0 && (l > 32 || (l & (l - 1)) != 0))
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": " + std::to_string(l) +
                        " neighbour lanes; give 0 (chosen for the renderer and the scene), 1, 2, "
                        "4, 8, 16 or 32");
    if (const std::uint32_t g = options.bodyGroupSize;
        g != 0 && (g < shared::kBodyLocalSize || g > shared::kBodyGroupSize || (g & (g - 1)) != 0))
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": a body pass of " + std::to_string(g) +
                        " invocations; give 0 (chosen for the renderer), 64, 128, 256 or 512");
    auto impl = std::make_unique<Impl>(scene);
    impl->options = options;
    impl->k = deriveConstants(scene.simulation);
    impl->capacity = std::max<std::uint32_t>(scene.simulation.capacity, 1);
    impl->maxIterations = std::max<std::uint32_t>(scene.simulation.maxIterations, 1);
    impl->tableSize = std::max<std::uint32_t>(1024, std::bit_ceil(2 * impl->capacity));
    impl->lanes = options.neighbourLanes != 0 ? options.neighbourLanes
                                              : neighbourLanesFor(impl->capacity);
    const std::uint64_t laneItems = std::uint64_t(impl->capacity) * impl->lanes;
    if (laneItems > 0xffffffffull)
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": a capacity of " + std::to_string(impl->capacity) +
                        " particles at " + std::to_string(impl->lanes) +
                        " neighbour lanes each is more invocations than one pass may have");
    impl->solveChunks = std::max<std::uint32_t>(
        1, std::uint32_t((std::uint64_t(gpu::groupCount(laneItems, shared::kPbfLocalSize)) +
                          kMaxGroupsPerDispatch - 1) /
                         kMaxGroupsPerDispatch));
    impl->colliderAssets = std::move(colliders);
    auto bodies = setUpBodies(scene, impl->colliderAssets, impl->k);
    if (!bodies)
        return bodies.error();
    impl->bodySetup = std::move(*bodies);
    impl->bodyCount = std::uint32_t(impl->bodySetup.records.size());

    if (auto ok = impl->compilePasses(); !ok)
        return ok.error();
    auto scan = PrefixScan::create(impl->tableSize + 1);
    if (!scan)
        return scan.error();
    impl->scan = std::make_unique<PrefixScan>(std::move(*scan));
    if (auto ok = impl->allocate(); !ok)
        return ok.error();

    // Every grid in one buffer, the dense ones first and then the sparse ones (32-byte aligned,
    // as NanoVDB lays out its nodes); the records point at their offsets.
    std::uint64_t offset = 0; // [words]
    std::uint64_t sparseOffset = denseBytes(impl->colliderAssets); // [bytes]
    for (const format::ColliderAsset& a : impl->colliderAssets) {
        if (a.sparse()) {
            impl->colliderRecords.push_back(colliderRecord(a, std::uint32_t(sparseOffset)));
            impl->sdfBuf.upload(a.grid.data(), a.grid.size(), sparseOffset);
            sparseOffset += sparseSlotBytes(a);
        } else {
            impl->colliderRecords.push_back(colliderRecord(a, std::uint32_t(offset)));
            impl->sdfBuf.upload(a.distances, offset * sizeof(float));
            offset += a.pointCount();
        }
    }
    for (std::size_t c = 0; c < impl->colliderRecords.size(); ++c) {
        shared::GpuCollider& r = impl->colliderRecords[c];
        r.friction = scene.colliders[c].friction;
        r.body = impl->bodySetup.bodyOfCollider[c];
        if (r.body == shared::kNoBody)
            continue;
        // A body's record starts at its initial pose, at rest; the body pass moves it.
        const ColliderPose start = bodyPose(impl->bodySetup.records[r.body]);
        r.worldToGrid = glm::inverse(poseMatrix(start));
        r.rotation = glm::mat4_cast(start.rotation);
        r.motion = glm::mat4(1.0f);
        r.scale = scene.colliders[c].scale;
    }
    impl->colliderBuf.upload(impl->colliderRecords);
    if (impl->bodyCount > 0) {
        impl->bodyBuf.upload(impl->bodySetup.records);
        impl->bodySamples.upload(impl->bodySetup.samples);
    }
    const std::uint32_t zeroWord = 0;
    glClearNamedBufferData(impl->bodySums.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT,
                           &zeroWord);

    const std::size_t ring = 8 + 2 * std::size_t(std::max(1u, scene.simulation.substeps));
    for (std::size_t p = 0; p < std::size_t(Pass::Count); ++p)
        impl->timers.emplace_back(ring);

    std::vector<ParticleState> initial = fillBlocks(scene);
    // Ids keep counting from the blocks' full count, so they do not depend on the bodies.
    const std::uint32_t blockParticles = std::uint32_t(initial.size());
    impl->removedAtSpawn = removeParticlesInBodies(scene, impl->colliderAssets, initial);
    if (initial.size() > impl->capacity)
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": the fluid blocks hold " + std::to_string(initial.size()) +
                        " particles but simulation.capacity is " + std::to_string(impl->capacity));
    impl->nextId = blockParticles;
    impl->append(initial);
    const std::uint32_t zero = 0;
    glClearNamedBufferData(impl->statsBuf.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    // Empty buckets: from here on, every scan leaves them so.
    glClearNamedBufferData(impl->cellCount.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    impl->uploadParams();
    return Simulation(std::move(impl));
}

Simulation::Simulation(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;
Simulation::~Simulation() = default;

void Simulation::step() {
    Impl& s = *m_impl;
    for (auto& timer : s.timers)
        timer.poll();
    s.capacityReached = false;
    s.fillStats(offsetof(shared::PbfStats, nonFinite), sizeof(std::uint32_t), 0);
    s.fillStats(offsetof(shared::PbfStats, maskOverflow), 5 * sizeof(std::uint32_t), 0);
    static_assert(offsetof(shared::PbfStats, solveDispatches) ==
                  offsetof(shared::PbfStats, maskOverflow) + 4 * sizeof(std::uint32_t));
    const std::uint32_t substeps = std::max(1u, s.scene.simulation.substeps);
    for (std::uint32_t i = 0; i < substeps; ++i) {
        s.substepInStep = i;
        s.substep();
    }

    // Step statistics: max speed and particles inside colliders, from the final state.
    s.begin(Pass::Stats);
    s.fillStats(offsetof(shared::PbfStats, insideColliders), sizeof(std::uint32_t), 0);
    s.fillStats(offsetof(shared::PbfStats, maxSpeedBits), sizeof(std::uint32_t), 0);
    if (s.count > 0) {
        s.memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        s.params.bindBase(GL_UNIFORM_BUFFER, shared::kBindParams);
        s.bindParticles(s.pos[s.cur], s.vel[s.cur]);
        s.statsBuf.bindStorage(shared::kBindStats);
        s.colliderBuf.bindStorage(shared::kBindColliders);
        s.sdfBuf.bindStorage(shared::kBindSdf);
        s.dispatch(s.stats, s.count);
    }
    s.end(Pass::Stats);
    s.memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
    ++s.steps;
}

StepStats Simulation::readStats() {
    Impl& s = *m_impl;
    StepStats out;
    out.step = s.steps;
    out.time = s.time;
    out.particles = s.count;
    out.capacityReached = s.capacityReached;
    // PbfStats, then PbfIterationStats[maxIterations]: one readback, then the parts by offset.
    std::vector<std::byte> raw(s.statsBuf.size());
    s.statsBuf.download(raw.data(), raw.size());
    shared::PbfStats header{};
    std::memcpy(&header, raw.data(), sizeof(header));
    out.nonFinite = header.nonFinite;
    out.insideColliders = header.insideColliders;
    out.maxSpeed = std::bit_cast<float>(header.maxSpeedBits);
    out.maskOverflow = header.maskOverflow;
    out.maxCandidates = header.maxCandidates;
    out.maxNeighbours = header.maxNeighbours;
    out.solveDispatches = header.solveDispatches;
    out.meanIterations =
        double(header.iterationSum) / double(std::max(1u, s.scene.simulation.substeps));
    const std::uint32_t stop = header.stopIteration;
    out.iterations = stop == kNoStop ? s.maxIterations : stop;
    const std::uint32_t slot = std::min(stop, s.maxIterations - 1);
    shared::PbfIterationStats it{};
    std::memcpy(&it, raw.data() + kStatsHeaderBytes + slot * sizeof(it), sizeof(it));
    if (it.particles > 0) {
        const double sum = (double(it.errorHi) * 4294967296.0 + double(it.errorLo)) /
                           double(shared::kErrorFixedScale);
        out.avgDensityError = sum / double(it.particles);
        out.maxDensityError = std::bit_cast<float>(it.errorMaxBits);
    }
    return out;
}

PassTimes Simulation::passTimes() {
    Impl& s = *m_impl;
    PassTimes times;
    times.fill(-1.0);
    if (!s.options.timers)
        return times;
    const double perStep = s.scene.simulation.substeps;
    for (std::size_t p = 0; p < times.size(); ++p) {
        gpu::GpuTimer& timer = s.timers[p];
        while (timer.poll()) {
        }
        if (timer.completed() == 0)
            continue;
        const double mean = double(timer.totalNs()) / double(timer.completed()) * 1e-6;
        times[p] = Pass(p) == Pass::Stats ? mean : mean * perStep;
    }
    return times;
}

PassTimes Simulation::drainPassTimes() {
    Impl& s = *m_impl;
    PassTimes times;
    times.fill(-1.0);
    if (!s.options.timers)
        return times;
    for (std::size_t p = 0; p < times.size(); ++p) {
        gpu::GpuTimer& timer = s.timers[p];
        if (timer.pending() > 0)
            timer.elapsedNs();
        const std::uint64_t total = timer.totalNs();
        times[p] = double(total - s.drainedNs[p]) * 1e-6;
        s.drainedNs[p] = total;
    }
    return times;
}

std::vector<ParticleState> Simulation::downloadParticles() const {
    const Impl& s = *m_impl;
    std::vector<ParticleState> out(s.count);
    if (s.count == 0)
        return out;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const auto p = s.pos[s.cur].download<glm::vec4>(0, s.count);
    const auto v = s.vel[s.cur].download<glm::vec4>(0, s.count);
    const auto ids = s.id[s.cur].download<std::uint32_t>(0, s.count);
    for (std::uint32_t i = 0; i < s.count; ++i)
        out[i] = ParticleState{glm::vec3(p[i]), glm::vec3(v[i]), ids[i]};
    return out;
}

Result<void> Simulation::setParameters(const format::SimulationParams& params) {
    Impl& s = *m_impl;
    format::SimulationParams p = params;
    const format::SimulationParams& now = s.scene.simulation;
    p.spacing = now.spacing;
    p.restDensity = now.restDensity;
    p.capacity = now.capacity;
    const float values[] = {p.kernelRadius, p.timeStep, p.targetDensityError, p.relaxation,
                            p.scorrK, p.scorrN, p.scorrDeltaQ, p.xsph, p.vorticity,
                            p.gravity.x, p.gravity.y, p.gravity.z};
    for (float v : values)
        if (!std::isfinite(v))
            return fail(ErrorCode::NonFinite, "simulation parameters: a value is not finite");
    auto bad = [](const std::string& what) {
        return fail(ErrorCode::InvalidArgument, "simulation parameters: " + what);
    };
    if (p.kernelRadius < 1.5f * p.spacing || p.kernelRadius > 4.0f * p.spacing)
        return bad("kernelRadius must lie in [1.5 spacing, 4 spacing]");
    if (!(p.timeStep > 0.0f) || p.substeps == 0 || p.minIterations == 0 || p.maxIterations == 0)
        return bad("timeStep, substeps and iterations must be > 0");
    if (p.minIterations > p.maxIterations)
        return bad("minIterations must not exceed maxIterations");
    if (p.scorrDeltaQ < 0.0f || p.scorrDeltaQ >= p.kernelRadius)
        return bad("scorrDeltaQ must lie in [0, kernelRadius)");
    if (p.targetDensityError < 0.0f || p.relaxation < 0.0f || p.scorrK < 0.0f ||
        p.scorrN < 1.0f || p.xsph < 0.0f || p.vorticity < 0.0f)
        return bad("targetDensityError, relaxation, scorrK, xsph and vorticity must be >= 0, "
                   "scorrN >= 1");
    // A larger h reads a dynamic body's distances further out: its sparse band must still hold
    // them, as when the scene was loaded.
    format::Scene changed = s.scene;
    changed.simulation = p;
    if (auto ok = checkColliderBands(changed, s.colliderAssets); !ok)
        return ok;
    if (p.maxIterations > s.maxIterations) {
        // The per-iteration statistics slots and the solve args grow with the cap. Both are
        // allocated before either replaces its buffer, so a failure leaves nothing changed.
        auto stats = gpu::Buffer::create(
            kStatsHeaderBytes + p.maxIterations * sizeof(shared::PbfIterationStats), "stats");
        if (!stats)
            return stats.error();
        auto args = gpu::Buffer::create(s.solveArgsBytes(p.maxIterations), "solve dispatch args");
        if (!args)
            return args.error();
        const std::uint32_t zero = 0;
        glClearNamedBufferData(stats->id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        s.statsBuf = std::move(*stats);
        s.solveArgs = std::move(*args);
    }
    s.maxIterations = p.maxIterations;
    s.scene.simulation = p;
    s.k = deriveConstants(p);
    return {};
}

const format::SimulationParams& Simulation::parameters() const {
    return m_impl->scene.simulation;
}

void Simulation::setEmittersEnabled(bool enabled) { m_impl->emittersOn = enabled; }
bool Simulation::emittersEnabled() const { return m_impl->emittersOn; }

Result<void> Simulation::setParticles(const std::vector<ParticleState>& particles) {
    Impl& s = *m_impl;
    if (particles.size() > s.capacity)
        return fail(ErrorCode::InvalidArgument, std::to_string(particles.size()) +
                                                    " particles do not fit the capacity " +
                                                    std::to_string(s.capacity));
    s.count = 0;
    s.append(particles);
    for (const ParticleState& p : particles)
        s.nextId = std::max(s.nextId, p.id + 1);
    return {};
}

std::uint32_t Simulation::particleCount() const { return m_impl->count; }
std::uint32_t Simulation::capacity() const { return m_impl->capacity; }
double Simulation::time() const { return m_impl->time; }
std::uint64_t Simulation::steps() const { return m_impl->steps; }
const gpu::Buffer& Simulation::positionBuffer() const { return m_impl->pos[m_impl->cur]; }
const gpu::Buffer& Simulation::velocityBuffer() const { return m_impl->vel[m_impl->cur]; }
std::uint64_t Simulation::gpuBytes() const { return m_impl->gpuBytes; }
std::uint64_t Simulation::bytesPerParticle() const { return m_impl->bytesPerParticle; }
GpuCommandCount Simulation::commandCount() const { return m_impl->commands; }
std::uint32_t Simulation::neighbourLanes() const { return m_impl->lanes; }

glm::uvec3 Simulation::neighbourGridCells() const { return m_impl->denseGridDims(); }
std::vector<std::uint32_t> Simulation::solveGroups() const {
    const Impl& s = *m_impl;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const auto args = s.solveArgs.download<shared::PbfDispatchArgs>(
        0, std::size_t(s.maxIterations) * s.solveChunks);
    std::vector<std::uint32_t> groups(s.maxIterations, 0);
    for (std::uint32_t it = 0; it < s.maxIterations; ++it)
        for (std::uint32_t c = 0; c < s.solveChunks; ++c)
            groups[it] += args[it * s.solveChunks + c].groupsX;
    return groups;
}
std::vector<Simulation::RecordedNeighbours> Simulation::recordedNeighbours() const {
    const Impl& s = *m_impl;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const std::uint32_t n = s.count;
    std::vector<RecordedNeighbours> out(n);
    if (n == 0)
        return out;
    const auto start = s.predStart.download<glm::vec4>(0, n);
    const auto ids = s.id[s.cur].download<std::uint32_t>(0, n);
    const auto cellStart = s.cellStart.download<std::uint32_t>();
    const auto mask = s.neighbourMask.download<std::uint32_t>(
        0, std::size_t(n) * shared::kNeighbourMaskWords);
    // The candidate ranges exactly as PBF_RANGES_BEGIN walks them (same float arithmetic).
    const glm::uvec3 dims = s.denseGridDims();
    const bool dense = dims.x > 0;
    const float invH = 1.0f / s.k.h, h2 = s.k.h * s.k.h;
    const glm::vec3 origin = dense ? *s.scene.domainMin : glm::vec3(0.0f);
    auto cellOf = [&](glm::vec3 x) {
        if (dense)
            return glm::clamp(glm::ivec3(glm::floor((x - origin) * invH)), glm::ivec3(0),
                              glm::ivec3(dims) - 1);
        return glm::ivec3(glm::floor(x * invH));
    };
    auto hashOf = [&](glm::ivec3 c) {
        return ((std::uint32_t(c.x) * 73856093u) ^ (std::uint32_t(c.y) * 19349663u) ^
                (std::uint32_t(c.z) * 83492791u)) &
               (s.tableSize - 1);
    };
    auto bucketOf = [&](glm::ivec3 c) {
        return std::uint32_t(c.x) + dims.x * (std::uint32_t(c.y) + dims.y * std::uint32_t(c.z));
    };
    for (std::uint32_t i = 0; i < n; ++i) {
        RecordedNeighbours& r = out[i];
        r.id = ids[i];
        r.start = glm::vec3(start[i]);
        const glm::ivec3 cell = cellOf(r.start);
        std::uint32_t c = 0;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= (dense ? -1 : 1); ++dx) {
                    const glm::ivec3 cc = cell + glm::ivec3(dx, dy, dz);
                    std::uint32_t begin = 0, end = 0;
                    if (dense) {
                        if (cc.y < 0 || cc.y >= int(dims.y) || cc.z < 0 || cc.z >= int(dims.z))
                            continue;
                        begin = cellStart[bucketOf({std::max(cell.x - 1, 0), cc.y, cc.z})];
                        end = cellStart[bucketOf({std::min(cell.x + 1, int(dims.x) - 1), cc.y,
                                                  cc.z}) + 1];
                    } else {
                        const std::uint32_t bucket = hashOf(cc);
                        begin = cellStart[bucket];
                        end = cellStart[bucket + 1];
                    }
                    for (std::uint32_t j = begin; j < end; ++j, ++c) {
                        if (c < shared::kNeighbourMaskBits) {
                            if ((mask[std::size_t(i) * shared::kNeighbourMaskWords + c / 32] >>
                                 (c % 32)) & 1u)
                                r.fromMask.push_back(ids[j]);
                            continue;
                        }
                        const glm::vec3 d = r.start - glm::vec3(start[j]);
                        if (j != i && (dense || cellOf(glm::vec3(start[j])) == cc) &&
                            glm::dot(d, d) < h2)
                            r.pastMask.push_back(ids[j]);
                    }
                }
        r.candidates = c;
    }
    return out;
}

std::vector<BodyState> Simulation::bodies() const {
    const Impl& s = *m_impl;
    std::vector<BodyState> out;
    if (s.bodyCount == 0)
        return out;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const auto records = s.bodyBuf.download<shared::GpuBody>(0, s.bodyCount);
    for (std::uint32_t b = 0; b < s.bodyCount; ++b) {
        const shared::GpuBody& r = records[b];
        BodyState state;
        state.collider = r.collider;
        state.mass = r.mass;
        state.volume = s.bodySetup.volumes[b];
        state.massFromMesh = s.bodySetup.fromMesh[b];
        state.position = r.position;
        state.pose = bodyPose(r);
        state.orientation = state.pose.rotation;
        state.linearVelocity = r.linearVelocity;
        state.angularVelocity = r.angularVelocity;
        state.force = r.force;
        state.torque = r.torque;
        state.contacts = r.contacts;
        state.contactDepth = r.contactDepth;
        // The upward force over the weight of the water the whole body would displace.
        const glm::vec3 g = s.scene.simulation.gravity;
        const double weight = double(glm::dot(g, g)) * s.scene.simulation.restDensity * state.volume;
        state.submergedShare =
            weight > 0.0 ? std::max(0.0, -double(glm::dot(r.force, g)) / weight) : 0.0;
        out.push_back(state);
    }
    return out;
}

std::vector<ColliderPose> Simulation::colliderPoses() const {
    const Impl& s = *m_impl;
    std::vector<ColliderPose> poses;
    for (const format::SceneCollider& c : s.scene.colliders)
        poses.push_back(colliderPose(c, float(s.time)));
    for (const BodyState& b : bodies())
        poses[b.collider] = b.pose;
    return poses;
}

Result<void> Simulation::setDrag(const std::optional<BodyDrag>& drag) {
    Impl& s = *m_impl;
    if (drag) {
        if (drag->body >= s.bodyCount)
            return fail(ErrorCode::InvalidArgument,
                        "drag: body " + std::to_string(drag->body) + " of " +
                            std::to_string(s.bodyCount));
        const float values[] = {drag->anchor.x, drag->anchor.y, drag->anchor.z,
                                drag->target.x, drag->target.y, drag->target.z};
        for (float v : values)
            if (!std::isfinite(v))
                return fail(ErrorCode::NonFinite, "drag: a point is not finite");
    }
    s.drag = drag;
    return {};
}

std::optional<BodyHit> Simulation::pickBody(glm::vec3 origin, glm::vec3 direction) const {
    const Impl& s = *m_impl;
    const float length = glm::length(direction);
    if (!(length > 0.0f) || !std::isfinite(length))
        return std::nullopt;
    const glm::vec3 dir = direction / length;
    std::optional<BodyHit> best;
    const std::vector<BodyState> states = bodies();
    for (std::uint32_t b = 0; b < states.size(); ++b) {
        const ColliderPose& pose = states[b].pose;
        const format::SdfSampler sampler(s.colliderAssets[states[b].collider]);
        // Sphere tracing in world units. Outside the grid box phi may overestimate the distance
        // (SdfSampler), so a step can end slightly inside: that still counts as the hit.
        const float reach = glm::length(origin - states[b].position) +
                            s.bodySetup.records[b].boundRadius;
        float t = 0.0f;
        for (int it = 0; it < 256 && t <= reach; ++it) {
            const glm::vec3 p = origin + t * dir;
            const float phi = pose.scale * sampler.value(glm::dvec3(pose.toLocal(p)));
            if (phi < 1e-4f * pose.scale) {
                if (!best || t < best->distance)
                    best = BodyHit{b, p, pose.toLocal(p), t};
                break;
            }
            t += std::max(phi, 1e-4f);
        }
    }
    return best;
}

std::uint32_t Simulation::particlesRemovedAtSpawn() const { return m_impl->removedAtSpawn; }

const PbfConstants& Simulation::constants() const { return m_impl->k; }
const format::Scene& Simulation::scene() const { return m_impl->scene; }

} // namespace sluice::rt
