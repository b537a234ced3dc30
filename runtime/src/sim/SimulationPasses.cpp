// The step, pass by pass, in the order of docs/pbf.md ("One substep at time t"): emit, predict,
// sort, solve, velocity, vorticity and XSPH, bodies; then the step's statistics.
#include "sim/SimulationImpl.h"

#include <numbers>

namespace sluice::rt {

void Simulation::Impl::bindParticles(const gpu::Buffer& posIn, const gpu::Buffer& velIn) const {
    posIn.bindStorage(shared::kBindPosIn);
    velIn.bindStorage(shared::kBindVelIn);
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
        applyVorticityAndXsph();
    }
    if (bodyCount > 0) {
        if (count == 0)
            bindSharedBuffers();
        integrateBodies();
    }
    if (forceMeter.any()) {
        if (count == 0 && bodyCount == 0)
            bindSharedBuffers();
        measureColliderForces();
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
    if (!emittersOn)
        emitters.skip(float(t0));
    else if (!emitters.emit(float(t0), count, capacity, nextId, staging))
        capacityReached = true;
    append(staging);
    uploadParams();
    uploadColliders(t0, t1);
    if (substepInStep == 0)
        moveKinematicBodies();
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
    bindColliders();
    const std::pair<const gpu::Buffer*, GLuint> storage[] = {
        {&statsBuf, shared::kBindStats},
        {&cellCount, shared::kBindCellCount},
        {&cellStart, shared::kBindCellStart},
        {&hash, shared::kBindHash},
        {&rank, shared::kBindRank},
        {&sortedToOld, shared::kBindSortedToOld},
        {&neighbourMask, shared::kBindNeighbourMask},
        {&collidersNear, shared::kBindCollidersNear},
        {&bodyBuf, shared::kBindBodies},
        {&bodySums, shared::kBindBodySums},
        {&bodySamples, shared::kBindBodySamples},
        {&bodySteps, shared::kBindBodySteps},
        {&solveArgs, shared::kBindSolveArgs}};
    for (const auto& [buffer, binding] : storage)
        buffer->bindStorage(binding);
}

// Step 2: x* into pred[0], and each particle counted into its bucket; the solve's dispatch
// args written for the indirect dispatches (hence the command barrier).
void Simulation::Impl::predictPositions() {
    begin(Pass::Predict);
    bindParticles(pos[cur], vel[cur]);
    pred[0].bindStorage(shared::kBindPredOut);
    id[cur].bindStorage(shared::kBindIdIn);
    removeIdBuf.bindStorage(shared::kBindRemoveIds);
    dispatch(predict, count);
    memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    // One-shot removals apply to this substep only.
    removeBoxes.clear();
    removeIdList.clear();
    end(Pass::Predict);
}

// Step 3: counting sort by bucket, then every particle reordered into the other buffers (x* of
// the sorted order into predStart). The scan gives each bucket its range, cellStart[b] ..
// cellStart[b + 1], and zeroes the counts for the next substep. Without --deterministic the
// reorder scatters each particle straight to its slot; with it, the slots are listed first
// (scatter), put in source order inside each bucket, then gathered.
void Simulation::Impl::sortIntoBuckets() {
    begin(Pass::Sort);
    // With removal, one bucket more: the removed particles', after every live one.
    const std::uint32_t buckets = activeBuckets() + (removal ? 1u : 0u);
    removedBucket = activeBuckets();
    sortedWithRemoval = removal;
    commands += scan->exclusive(cellCount, cellStart, ScanInput{buckets + 1, buckets, true});
    cellStart.bindStorage(shared::kBindCellStart);
    cellCount.bindStorage(shared::kBindCellCount);
    if (options.deterministic) {
        dispatch(scatter, count);
        barrier();
        // The removed particles' bucket keeps the atomics' order: they are no longer simulated.
        dispatch(bucketSort, activeBuckets());
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
// Step 5 (velocity, x <- x*) is done by the delta dispatch that ends the solve, the one that
// meets the target or the last: it writes x* into pos[cur] and the velocities into
// vel[1 - cur].
void Simulation::Impl::solve() {
    begin(Pass::Solve);
    predStart.bindStorage(shared::kBindPredStart);
    bindParticles(pos[cur], vel[cur]);
    vel[1 - cur].bindStorage(shared::kBindVelOut);
    const gpu::Buffer* in = &predStart;
    const gpu::BufferTexture* inTexels = &neighbourTexels.start;
    for (std::uint32_t it = 0; it < maxIterations; ++it) {
        in->bindStorage(shared::kBindPredIn);
        bindNeighbourTexels(*inTexels);
        lambda.set("iteration", it);
        dispatchSolve(lambda, it);
        barrier();
        pred[it % 2].bindStorage(shared::kBindPredOut);
        delta.set("iteration", it);
        dispatchSolve(delta, it);
        memoryBarrier(passBarrierBits() | GL_COMMAND_BARRIER_BIT);
        in = &pred[it % 2];
        inTexels = &neighbourTexels.pred[it % 2];
    }
    end(Pass::Solve);
}

// Step 6: vorticity confinement and XSPH, back into vel[cur]. The vorticity omega goes into
// pos[1 - cur], the positions before this substep's reorder, which nothing reads again: the
// next reorder overwrites them (16 bytes a particle saved).
void Simulation::Impl::applyVorticityAndXsph() {
    begin(Pass::Vorticity);
    const bool withVorticity = scene.simulation.vorticity > 0.0f;
    pos[1 - cur].bindStorage(shared::kBindOmega);
    vel[1 - cur].bindStorage(shared::kBindVelIn);
    bindNeighbourTexels(neighbourTexels.pos[cur], &neighbourTexels.vel[1 - cur],
                        &neighbourTexels.pos[1 - cur]);
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

// After step 7, the body pass (docs/bodies.md, "The body pass"): the bodies take the fluid's
// reaction, move, meet each other and the walls, and rewrite their collider records; one work
// group per body. The start and each Jacobi sweep of the contacts are a dispatch of their own,
// the bodies exchanging poses between them; one body needs no exchange, so it takes one.
void Simulation::Impl::integrateBodies() {
    begin(Pass::Bodies);
    bodies.set("dragBody", drag ? drag->body : shared::kNoBody);
    bodies.set("dragAnchor", drag ? drag->anchor : glm::vec3(0.0f));
    bodies.set("dragTarget", drag ? drag->target : glm::vec3(0.0f));
    bodies.set("dragOmega", 2.0f * std::numbers::pi_v<float> * shared::kDragSpringHz);
    bodies.set("firstSubstep", substepInStep == 0 ? 1u : 0u);
    bodies.set("substepShare", 1.0f / float(std::max(1u, scene.simulation.substeps)));
    bodies.use();
    // The last sweep writes the bodies' collider records, which the next passes read as a
    // uniform block.
    const auto run = [&](std::uint32_t withStart, std::uint32_t sweepBegin,
                         std::uint32_t sweepEnd) {
        bodies.set("withStart", withStart);
        bodies.set("sweepBegin", sweepBegin);
        bodies.set("sweepEnd", sweepEnd);
        glDispatchCompute(bodyCount, 1, 1);
        ++commands.dispatches;
        memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT |
                      (sweepEnd == shared::kBodyContactSweeps ? GL_UNIFORM_BARRIER_BIT : 0));
    };
    if (bodyCount == 1) {
        run(1, 0, shared::kBodyContactSweeps);
    } else {
        run(1, 0, 0);
        for (std::uint32_t sweep = 0; sweep < shared::kBodyContactSweeps; ++sweep)
            run(0, sweep, sweep + 1);
    }
    end(Pass::Bodies);
}

// After the solve, the forces on the measured static and kinematic colliders
// (pbf_collider_forces.comp): their push sums into force and torque, the sums zeroed.
void Simulation::Impl::measureColliderForces() {
    commands.dispatches +=
        forceMeter.run(substepInStep == 0, 1.0f / float(std::max(1u, scene.simulation.substeps)));
    memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

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
        s.bindColliders();
        s.dispatch(s.stats, s.count);
    }
    s.end(Pass::Stats);
    s.memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
    ++s.steps;
    if (s.bodyCount > 0)
        s.snapshotBodies();
    if (s.forceMeter.any())
        s.forceMeter.snapshot(s.steps, s.time);
    if (s.removal)
        s.trimRemoved();
    s.updateDrawArgs();
}

} // namespace sluice::rt
