// What comes back from the GPU: step statistics, pass times, particles, bodies and collider
// poses, picking, and the test hooks' buffers. Each readback waits for the GPU.
#include "sim/SimulationImpl.h"

namespace sluice::rt {

StepStats Simulation::readStats() {
    Impl& s = *m_impl;
    StepStats out;
    out.step = s.steps;
    out.time = s.time;
    out.particles = s.liveNow();
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
    out.bodyFaults = header.bodyFaults;
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
    std::vector<ParticleState> out;
    if (s.count == 0)
        return out;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const auto p = s.pos[s.cur].download<glm::vec4>(0, s.count);
    const auto v = s.vel[s.cur].download<glm::vec4>(0, s.count);
    const auto ids = s.id[s.cur].download<std::uint32_t>(0, s.count);
    out.reserve(s.count);
    for (std::uint32_t i = 0; i < s.count; ++i)
        if (p[i].w == 0.0f) // w = 1: removed, not yet compacted away (pbf_reorder.comp)
            out.push_back(ParticleState{glm::vec3(p[i]), glm::vec3(v[i]), ids[i]});
    return out;
}

Result<void> Simulation::Impl::allocateRemoval(std::size_t ids) {
    const std::size_t bytes = std::max<std::size_t>(1, ids) * sizeof(std::uint32_t);
    if (removeIdBuf.size() < bytes) {
        auto buffer = gpu::Buffer::create(bytes, "removal ids");
        if (!buffer)
            return buffer.error();
        removeIdBuf = std::move(*buffer);
    }
    for (LiveRecord& record : liveRecords)
        if (record.word.size() == 0) {
            auto word = gpu::Buffer::create(sizeof(std::uint32_t), "live count");
            if (!word)
                return word.error();
            record.word = std::move(*word);
        }
    return {};
}

void Simulation::Impl::trimRemoved() {
    // The newest completed copy taken since the count last dropped: the last count - live of
    // its slots were removed, and they are still the last slots (a removed particle never comes
    // back, and every sort since put the removed ones after the live ones).
    const std::size_t n = liveRecords.size();
    for (std::size_t back = 1; back <= n; ++back) {
        LiveRecord& record = liveRecords[(nextLive + n - back) % n];
        if (!record.fence.pending() || record.step < lastTrim || !record.fence.signalled(false))
            continue;
        std::uint32_t live = 0;
        record.word.download(&live, sizeof(live));
        if (live < record.count) {
            count -= record.count - live;
            lastTrim = steps;
            for (LiveRecord& other : liveRecords)
                other.fence.reset();
        }
        break;
    }
    if (count == 0 || !sortedWithRemoval)
        return;
    LiveRecord& record = liveRecords[nextLive];
    nextLive = (nextLive + 1) % n;
    glCopyNamedBufferSubData(cellStart.id(), record.word.id(),
                             GLintptr(removedBucket) * GLintptr(sizeof(std::uint32_t)), 0,
                             sizeof(std::uint32_t));
    record.fence = Fence::insert();
    record.step = steps;
    record.count = count;
}

std::uint32_t Simulation::Impl::liveNow() const {
    if (!removal || count == 0 || !sortedWithRemoval)
        return count;
    std::uint32_t live = 0;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    cellStart.download(&live, sizeof(live), std::size_t(removedBucket) * sizeof(live));
    return std::min(live, count);
}

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
Simulation::NeighbourState Simulation::neighbourState() const {
    const Impl& s = *m_impl;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    NeighbourState out;
    const std::uint32_t n = s.count;
    out.gridDims = s.denseGridDims();
    out.gridOrigin = out.gridDims.x > 0 ? *s.scene.domainMin : glm::vec3(0.0f);
    out.h = s.k.h;
    out.tableSize = s.tableSize;
    if (n == 0)
        return out;
    out.start = s.predStart.download<glm::vec4>(0, n);
    out.ids = s.id[s.cur].download<std::uint32_t>(0, n);
    out.cellStart = s.cellStart.download<std::uint32_t>();
    out.mask =
        s.neighbourMask.download<std::uint32_t>(0, std::size_t(n) * shared::kNeighbourMaskWords);
    return out;
}

std::vector<BodyState>
Simulation::Impl::bodyStates(const std::vector<shared::GpuBody>& records) const {
    std::vector<BodyState> out;
    for (std::uint32_t b = 0; b < records.size(); ++b) {
        const shared::GpuBody& r = records[b];
        BodyState state;
        state.collider = r.collider;
        state.mass = r.mass;
        state.volume = bodySetup.volumes[b];
        state.massFromMesh = bodySetup.fromMesh[b];
        state.position = r.position;
        state.pose = bodyPose(r);
        state.orientation = state.pose.rotation;
        state.linearVelocity = r.linearVelocity;
        state.angularVelocity = r.angularVelocity;
        state.force = r.force;
        state.torque = r.torque;
        state.contacts = r.contacts;
        state.contactDepth = r.contactDepth;
        state.kinematic = r.kinematic != 0;
        // The upward force over the weight of the water the whole body would displace.
        const glm::vec3 g = scene.simulation.gravity;
        const double weight = double(glm::dot(g, g)) * scene.simulation.restDensity * state.volume;
        state.submergedShare =
            weight > 0.0 ? std::max(0.0, -double(glm::dot(r.force, g)) / weight) : 0.0;
        out.push_back(state);
    }
    return out;
}

std::vector<BodyState> Simulation::bodies() const {
    const Impl& s = *m_impl;
    if (s.bodyCount == 0)
        return {};
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    return s.bodyStates(s.bodyBuf.download<shared::GpuBody>(0, s.bodyCount));
}

Result<void> Simulation::Impl::allocateBodySnapshots() {
    for (BodySnapshot& snapshot : bodySnapshots) {
        auto records = gpu::Buffer::create(bodyCount * sizeof(shared::GpuBody), "body snapshot");
        if (!records)
            return records.error();
        snapshot.records = std::move(*records);
    }
    return {};
}

void Simulation::Impl::snapshotBodies() {
    BodySnapshot& snapshot = bodySnapshots[nextSnapshot];
    nextSnapshot = (nextSnapshot + 1) % bodySnapshots.size();
    // step() ends with a buffer-update barrier, so the copy sees the body pass's writes.
    glCopyNamedBufferSubData(bodyBuf.id(), snapshot.records.id(), 0, 0,
                             GLsizeiptr(bodyCount * sizeof(shared::GpuBody)));
    snapshot.fence = Fence::insert();
    snapshot.step = steps;
    snapshot.time = time;
}

std::optional<BodiesReading> Simulation::latestBodies() const {
    const Impl& s = *m_impl;
    if (s.bodyCount == 0)
        return std::nullopt;
    const Impl::BodySnapshot* snapshot = newestPassed(s.bodySnapshots, s.nextSnapshot);
    if (snapshot == nullptr)
        return std::nullopt;
    BodiesReading reading;
    reading.step = snapshot->step;
    reading.time = snapshot->time;
    reading.bodies = s.bodyStates(snapshot->records.download<shared::GpuBody>(0, s.bodyCount));
    return reading;
}

std::vector<ColliderPose> Simulation::colliderPoses() const {
    const Impl& s = *m_impl;
    std::vector<ColliderPose> poses;
    for (std::size_t c = 0; c < s.scene.colliders.size(); ++c)
        poses.push_back(s.poseOf(c, float(s.time)));
    for (const BodyState& b : bodies())
        poses[b.collider] = b.pose;
    return poses;
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
        const float reach =
            glm::length(origin - states[b].position) + s.bodySetup.records[b].boundRadius;
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

} // namespace sluice::rt
