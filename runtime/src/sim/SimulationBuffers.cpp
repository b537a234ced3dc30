// Simulation's buffers, uploads and programs: allocation, the collider grids, the parameter
// block and poses (uploaded when they change), new particles, and the passes' compilation.
#include "sim/SimulationImpl.h"

namespace sluice::rt {

Result<void> Simulation::Impl::size(const SimulationOptions& o) {
    options = o;
    k = deriveConstants(scene.simulation);
    capacity = std::max<std::uint32_t>(scene.simulation.capacity, 1);
    maxIterations = std::max<std::uint32_t>(scene.simulation.maxIterations, 1);
    tableSize = std::max<std::uint32_t>(1024, std::bit_ceil(2 * capacity));
    lanes = o.neighbourLanes != 0 ? o.neighbourLanes : neighbourLanesFor(capacity);
    const std::uint64_t laneItems = std::uint64_t(capacity) * lanes;
    if (laneItems > 0xffffffffull)
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": a capacity of " + std::to_string(capacity) + " particles at " +
                        std::to_string(lanes) +
                        " neighbour lanes each is more invocations than one pass may have");
    solveChunks = std::max<std::uint32_t>(
        1, std::uint32_t((std::uint64_t(gpu::groupCount(laneItems, shared::kPbfLocalSize)) +
                          kMaxGroupsPerDispatch - 1) /
                         kMaxGroupsPerDispatch));
    return {};
}

std::vector<Simulation::Impl::BufferSpec> Simulation::Impl::bufferSpecs(std::uint64_t sdfBytes) {
    const std::uint64_t n = capacity;
    const std::uint64_t v4 = 16, u = 4;
    const bool withBodies = !bodySetup.records.empty(); // the colliders-near mask is theirs
    return {
        {&pos[0], n * v4, "pos 0"},
        {&pos[1], n * v4, "pos 1"},
        {&vel[0], n * v4, "vel 0"},
        {&vel[1], n * v4, "vel 1"},
        {&pred[0], n * v4, "pred 0"},
        {&pred[1], n * v4, "pred 1"},
        {&predStart, n * v4, "predStart"},
        {&id[0], n * u, "id 0"},
        {&id[1], n * u, "id 1"},
        {&hash, n * u, "hash"},
        {&rank, n * u, "rank"},
        {&sortedToOld, n * u, "sortedToOld"},
        // The bucket after the last holds the removed particles (docs/embedding.md).
        {&cellCount, (tableSize + 1) * u, "cellCount"},
        {&neighbourMask, n * shared::kNeighbourMaskWords * u, "neighbour mask"},
        {&collidersNear, (withBodies ? n : 1) * 4 * u, "colliders near"},
        {&cellStart, (tableSize + 2) * u, "cellStart"},
        {&statsBuf, kStatsHeaderBytes + maxIterations * sizeof(shared::PbfIterationStats), "stats"},
        {&colliderBuf, kColliderRecordBytes, "colliders"},
        {&sdfBuf, std::max<std::uint64_t>(u, sdfBytes), "sdf"},
        {&params, sizeof(shared::PbfParams), "params"},
        {&bodyBuf, std::max<std::uint64_t>(1, bodySetup.records.size()) * sizeof(shared::GpuBody),
         "bodies"},
        // The bodies' slots, then one per collider for its force when measured.
        {&bodySums,
         std::max<std::uint64_t>(1, bodySetup.records.size() + scene.colliders.size()) *
             shared::kBodySumWords * u,
         "body sums"},
        {&bodySamples, std::max<std::uint64_t>(1, bodySetup.samples.size()) * v4,
         "body contact points"},
        {&bodySteps,
         std::max<std::uint64_t>(1, bodySetup.records.size()) * sizeof(shared::GpuBodyStep),
         "body pass state"},
        {&solveArgs, solveArgsBytes(maxIterations), "solve dispatch args"},
        {&drawArgs, 4 * u, "draw args"}, // the view's DrawArraysIndirectCommand
    };
}

Result<void> Simulation::Impl::allocate() {
    const std::uint64_t n = capacity;
    const std::uint64_t v4 = 16, u = 4;
    GLint64 maxSsbo = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxSsbo);
    const std::uint64_t sdfBytes = sdfBufferBytes(maxSsbo);
    if (sdfBytes > 0xffffffffull) // GpuCollider::sdfOffset and PNanoVDB's addresses: 32 bits
        return fail(ErrorCode::GpuOutOfMemory,
                    scene.path + ": the colliders' grids take " + std::to_string(sdfBytes) +
                        " bytes, more than the 4 GiB the solver can address; coarsen them or "
                        "bake the large ones with `sluice-bake bake --sparse`");
    const std::vector<BufferSpec> allocs = bufferSpecs(sdfBytes);
    std::uint64_t total = 0;
    for (const BufferSpec& a : allocs)
        total += a.bytes;
    gpuBytes = total;
    // Per particle of capacity: the particle arrays (7 vec4, 5 uint; the vorticity omega lives
    // in the idle position buffer, applyVorticityAndXsph), the neighbour mask and the hash
    // table's cellCount + cellStart, spread over the capacity and rounded up; with bodies, the
    // masks of the colliders near each particle (its substep's and its iteration's).
    bytesPerParticle = 7 * v4 + 5 * u + shared::kNeighbourMaskWords * u +
                       (u * (2 * std::uint64_t(tableSize) + 3) + n - 1) / n +
                       (!bodySetup.records.empty() ? 4 * u : 0);
    for (const BufferSpec& a : allocs) {
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
    if (auto ok = viewSdfAsTexels(); !ok)
        return ok;
    return viewNeighboursAsTexels();
}

Result<void> Simulation::Impl::viewSdfAsTexels() {
    if (!sdfAsTexels)
        return {};
    auto texels = gpu::BufferTexture::createR32F(sdfBuf, "sdf texels");
    if (!texels)
        return fail(texels.error().code, scene.path + ": " + texels.error().detail);
    sdfTexels = std::move(*texels);
    return {};
}

Result<void> Simulation::Impl::viewNeighboursAsTexels() {
    if (!neighboursAsTexels)
        return {};
    using gpu::TexelFormat;
    NeighbourTexels& t = neighbourTexels;
    struct View {
        gpu::BufferTexture* texture;
        const gpu::Buffer& buffer;
        TexelFormat format;
        const char* label;
    };
    const View views[] = {
        {&t.start, predStart, TexelFormat::RGBA32F, "predStart texels"},
        {&t.pred[0], pred[0], TexelFormat::RGBA32F, "pred 0 texels"},
        {&t.pred[1], pred[1], TexelFormat::RGBA32F, "pred 1 texels"},
        {&t.pos[0], pos[0], TexelFormat::RGBA32F, "pos 0 texels"},
        {&t.pos[1], pos[1], TexelFormat::RGBA32F, "pos 1 texels"},
        {&t.vel[0], vel[0], TexelFormat::RGBA32F, "vel 0 texels"},
        {&t.vel[1], vel[1], TexelFormat::RGBA32F, "vel 1 texels"},
        {&t.mask, neighbourMask, TexelFormat::R32UI, "neighbour mask texels"},
        {&t.cellStart, cellStart, TexelFormat::R32UI, "cellStart texels"},
    };
    for (const View& v : views) {
        auto texture = gpu::BufferTexture::create(v.buffer, v.format, v.label);
        if (!texture)
            return fail(texture.error().code, scene.path + ": " + texture.error().detail);
        *v.texture = std::move(*texture);
    }
    return {};
}

void Simulation::Impl::bindNeighbourTexels(const gpu::BufferTexture& positions,
                                           const gpu::BufferTexture* velocities,
                                           const gpu::BufferTexture* omega) const {
    if (!neighboursAsTexels)
        return;
    neighbourTexels.start.bindTexture(shared::kUnitStartTexels);
    neighbourTexels.mask.bindTexture(shared::kUnitMaskTexels);
    neighbourTexels.cellStart.bindTexture(shared::kUnitCellStartTexels);
    positions.bindTexture(shared::kUnitPosTexels);
    if (velocities != nullptr)
        velocities->bindTexture(shared::kUnitVelTexels);
    if (omega != nullptr)
        omega->bindTexture(shared::kUnitOmegaTexels);
}

void Simulation::Impl::uploadColliderGrids() {
    // Every grid in one buffer, the dense ones first and then the sparse ones (32-byte aligned,
    // as NanoVDB lays out its nodes); the records point at their offsets.
    std::uint64_t offset = 0;                                // [words]
    std::uint64_t sparseOffset = denseBytes(colliderAssets); // [bytes]
    for (const format::ColliderAsset& a : colliderAssets) {
        if (a.sparse()) {
            colliderRecords.push_back(colliderRecord(a, std::uint32_t(sparseOffset)));
            sdfBuf.upload(a.grid.data(), a.grid.size(), sparseOffset);
            sparseOffset += sparseSlotBytes(a);
        } else {
            colliderRecords.push_back(colliderRecord(a, std::uint32_t(offset)));
            sdfBuf.upload(a.distances, offset * sizeof(float));
            offset += a.pointCount();
        }
    }
    for (std::size_t c = 0; c < colliderRecords.size(); ++c) {
        shared::GpuCollider& r = colliderRecords[c];
        r.friction = scene.colliders[c].friction;
        r.body = bodySetup.bodyOfCollider[c];
        if (r.body == shared::kNoBody)
            continue;
        // A body's record starts at its initial pose, at rest; the body pass moves it.
        const ColliderPose start = bodyPose(bodySetup.records[r.body]);
        r.worldToGrid = glm::inverse(poseMatrix(start));
        r.boundCentre = bodySetup.records[r.body].position;
        r.boundRadius = bodySetup.records[r.body].boundRadius;
        r.motion = glm::mat4(1.0f);
        r.scale = scene.colliders[c].scale;
    }
    // Volume maps after every grid (VolumeMaps.cpp builds them).
    std::uint64_t mapOffset = colliderDataBytes(colliderAssets) / sizeof(float); // [words]
    for (std::size_t c = 0; c < colliderRecords.size(); ++c) {
        if (!wantsVolumeMap(c))
            continue;
        colliderRecords[c].volumeMap = std::uint32_t(mapOffset);
        mapOffset += volumeMapPoints(c);
    }
    // The records past the scene's are zeros (no pass reads them: every loop stops at
    // colliderCount).
    const std::uint32_t zero = 0;
    glClearNamedBufferData(colliderBuf.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    colliderBuf.upload(colliderRecords);
    if (bodyCount > 0) {
        bodyBuf.upload(bodySetup.records);
        bodySamples.upload(bodySetup.samples);
    }
    const std::uint32_t zeroWord = 0;
    glClearNamedBufferData(bodySums.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zeroWord);
}

Result<void> Simulation::Impl::fillBlocks() {
    std::vector<ParticleState> initial = rt::fillBlocks(scene);
    // Ids keep counting from the blocks' full count, so they do not depend on the bodies.
    const std::uint32_t blockParticles = std::uint32_t(initial.size());
    removedAtSpawn = removeParticlesInBodies(scene, colliderAssets, initial);
    if (initial.size() > capacity)
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": the fluid blocks hold " + std::to_string(initial.size()) +
                        " particles but simulation.capacity is " + std::to_string(capacity));
    nextId = blockParticles;
    append(initial);
    return {};
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
    p.staticColliders = 0;
    for (std::size_t c = 0; c < std::min<std::size_t>(colliderRecords.size(), 32); ++c)
        if (colliderRecords[c].body == shared::kNoBody)
            p.staticColliders |= 1u << c;
    p.minIterations = s.minIterations;
    p.solveChunks = solveChunks;
    p.activeBuckets = activeBuckets();
    p.deterministic = options.deterministic ? 1u : 0u;
    p.maxIterations = maxIterations;
    p.bodyCount = bodyCount;
    p.particleMass = k.mass;
    p.boundaryScale = k.boundaryScale;
    p.bodyOffset = k.bodyOffset;
    p.removal = removal ? 1u : 0u;
    p.measuredForces = forceMeter.any() ? 1u : 0u;
    std::uint32_t boxes = 0;
    for (const std::vector<format::Drain>* list : {&drains, &removeBoxes})
        for (const format::Drain& d : *list) {
            p.drainMin[boxes] = glm::vec4(d.min, 0.0f);
            p.drainMax[boxes] = glm::vec4(d.max, 0.0f);
            ++boxes;
        }
    p.drainCount = boxes;
    p.removeIdCount = std::uint32_t(removeIdList.size());
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
        const ColliderPose now = poseOf(c, float(t1));
        const ColliderPose before = poseOf(c, float(t0));
        const glm::mat4 world = poseMatrix(now);
        shared::GpuCollider& r = colliderRecords[c];
        const shared::GpuCollider uploaded = r;
        r.worldToGrid = glm::inverse(world);
        r.motion = poseMatrix(before) * r.worldToGrid;
        r.scale = now.scale;
        r.forcePoint = now.translation;
        r.forceSlot = forceMeter.slotOf(c);
        // A static collider's record is uploaded once; a kinematic one's when it moved (or its
        // force is measured from now on, or no longer).
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
    if (!sortedWithRemoval)
        updateDrawArgs();
}

void Simulation::Impl::updateDrawArgs() {
    if (sortedWithRemoval && count > 0) {
        glCopyNamedBufferSubData(cellStart.id(), drawArgs.id(),
                                 GLintptr(removedBucket) * GLintptr(sizeof(std::uint32_t)), 0,
                                 sizeof(std::uint32_t));
        return;
    }
    const std::uint32_t command[4] = {count, 1, 0, 0}; // count, instances, first, base instance
    drawArgs.upload(command);
}

// Compiles every pass of the step with the defines this simulation needs.
Result<void> Simulation::Impl::compilePasses() {
    struct Build {
        gpu::Program* program;
        const char* name;
    };
    const Build builds[] = {
        {&predict, "pbf_predict.comp"},
        {&scatter, "pbf_scatter.comp"},
        {&bucketSort, "pbf_bucket_sort.comp"},
        {&reorder, "pbf_reorder.comp"},
        {&scatterReorder, "pbf_reorder.comp"},
        {&lambda, "pbf_lambda.comp"},
        {&delta, "pbf_delta.comp"},
        {&vorticity, "pbf_vorticity.comp"},
        {&confine, "pbf_confine.comp"},
        {&stats, "pbf_stats.comp"},
        {&bodies, "pbf_bodies.comp"},
    };
    // The dense samples are fetched through a texel view of the SDF buffer where every grid and
    // map fits one (an upper bound of the buffer allocate() makes), else read from storage.
    sdfAsTexels = !options.sdfFromStorage &&
                  colliderDataBytes(colliderAssets) + volumeMapWords() * sizeof(float) <=
                      gpu::BufferTexture::maxTexels() * sizeof(float);
    // The neighbour passes fetch through texel views where each buffer they read at other
    // particles' indices fits one (the mask is the largest: kNeighbourMaskWords per particle).
    const std::uint64_t mostNeighbourTexels = std::max<std::uint64_t>(
        std::uint64_t(capacity) * shared::kNeighbourMaskWords, std::uint64_t(tableSize) + 1);
    neighboursAsTexels =
        !options.neighboursFromStorage && mostNeighbourTexels <= gpu::BufferTexture::maxTexels();
    // NanoVDB's reader (glsl/NanoVdbGlsl.h) is compiled in only when a collider needs it.
    std::vector<gpu::ShaderDefine> defines = colliderDefines();
    if (!neighboursAsTexels)
        defines.push_back({"SLUICE_NEIGHBOURS_STORAGE", "1"});
    // A body's work group in the body pass (pbf_bodies.comp): kBodyLanes invocations on a GPU,
    // kBodyLanesSoftware on a software renderer, which runs a group's invocations a SIMD vector
    // at a time on one CPU thread.
    const std::uint32_t group =
        options.bodyGroupSize != 0 ? options.bodyGroupSize : bodyGroupSize();
    std::vector<gpu::ShaderDefine> bodyDefines(defines.begin(), defines.end());
    bodyDefines.push_back({"SLUICE_BODY_LANES", std::to_string(group)});
    std::vector<gpu::ShaderDefine> scatterDefines(defines.begin(), defines.end());
    scatterDefines.push_back({"PBF_SCATTER_REORDER", "1"});
    // The neighbour passes split each particle over its lanes; predict sizes their dispatches.
    std::vector<gpu::ShaderDefine> laneDefines(defines.begin(), defines.end());
    laneDefines.push_back({"PBF_LANES", std::to_string(lanes)});
    const gpu::Program* const laned[] = {&predict, &lambda, &delta, &vorticity, &confine};
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

} // namespace sluice::rt
