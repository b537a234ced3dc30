// Simulation: the calls a game loop makes between steps (docs/embedding.md): the fixed-step
// driver, collider poses it sets, particles it adds, and the view of the buffers it draws.
#include "sim/SimulationImpl.h"
#include "sluice/format/scene/SceneDefaults.h"

namespace sluice::rt {
namespace {

bool finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

} // namespace

Result<FrameAdvance> Simulation::advance(double frameSeconds, std::uint32_t maxSteps) {
    Impl& s = *m_impl;
    if (!std::isfinite(frameSeconds) || frameSeconds < 0.0)
        return fail(ErrorCode::InvalidArgument, "advance: a frame of " +
                                                    std::to_string(frameSeconds) +
                                                    " s; give a finite time >= 0");
    if (maxSteps == 0)
        return fail(ErrorCode::InvalidArgument, "advance: maxSteps is 0; give at least 1");
    const double dt = s.scene.simulation.timeStep;
    double owed = s.carried + frameSeconds;
    // A frame that owes a whole step to within rounding takes it: frames of 1/60 s in double
    // step once each at the float time step 1/60 s, which is 4e-8 of a step longer.
    const double whole = std::floor(owed / dt + 1e-5);
    FrameAdvance out;
    out.steps = std::uint32_t(std::min(whole, double(maxSteps)));
    if (whole > double(maxSteps))
        out.dropped = (whole - double(maxSteps)) * dt;
    owed -= double(out.steps) * dt + out.dropped;
    for (std::uint32_t i = 0; i < out.steps; ++i)
        step();
    s.carried = std::clamp(owed, 0.0, std::nextafter(dt, 0.0));
    out.remainder = s.carried;
    out.alpha = std::min(s.carried / dt, std::nextafter(1.0, 0.0));
    return out;
}

Result<void> Simulation::setColliderPose(std::uint32_t collider, glm::vec3 translation,
                                         glm::quat rotation) {
    Impl& s = *m_impl;
    const std::string what = "collider " + std::to_string(collider);
    if (collider >= s.scene.colliders.size())
        return fail(ErrorCode::InvalidArgument, "setColliderPose: " + what + " of " +
                                                    std::to_string(s.scene.colliders.size()) +
                                                    " colliders");
    const std::uint32_t body = s.bodySetup.bodyOfCollider[collider];
    if (body != shared::kNoBody && !s.kinematic[body])
        return fail(ErrorCode::InvalidArgument,
                    "setColliderPose: " + what +
                        " is a dynamic body, which the fluid moves; hand it to the game with "
                        "setBodyKinematic first, or move it at once with teleportBody");
    if (!finite(translation) || !std::isfinite(rotation.x) || !std::isfinite(rotation.y) ||
        !std::isfinite(rotation.z) || !std::isfinite(rotation.w))
        return fail(ErrorCode::NonFinite,
                    "setColliderPose: " + what + ": a pose that is not finite");
    const float length = glm::length(rotation);
    if (!(length > 0.0f) || !std::isfinite(length))
        return fail(ErrorCode::InvalidArgument,
                    "setColliderPose: " + what + ": the rotation is a zero quaternion");
    // A unit quaternion as a float holds it is kept bit for bit (the same pose as a keyframe's).
    const glm::quat unit = std::abs(length - 1.0f) > 1e-5f ? rotation / length : rotation;
    const ColliderPose to{translation, unit, s.scene.colliders[collider].scale};
    if (body != shared::kNoBody) {
        s.kinematic[body]->to = to;
        return {};
    }
    const float t0 = float(s.time);
    const float t1 = float(s.time + double(s.k.dt) * std::max(1u, s.scene.simulation.substeps));
    s.driven[collider] = Impl::DrivenPose{s.poseOf(collider, t0), t0, to, t1};
    return {};
}

Result<void> Simulation::teleportBody(std::uint32_t collider, glm::vec3 translation,
                                      glm::quat rotation, glm::vec3 linearVelocity,
                                      glm::vec3 angularVelocity) {
    Impl& s = *m_impl;
    const std::string what = "teleportBody: collider " + std::to_string(collider);
    auto body = s.bodyOf("teleportBody", collider, "place it with setColliderPose");
    if (!body)
        return body.error();
    const std::uint32_t b = *body;
    if (!finite(translation) || !finite(linearVelocity) || !finite(angularVelocity) ||
        !finite(glm::vec3(rotation.x, rotation.y, rotation.z)) || !std::isfinite(rotation.w))
        return fail(ErrorCode::NonFinite, what + ": a pose or velocity that is not finite");
    const float length = glm::length(rotation);
    if (!(length > 0.0f) || !std::isfinite(length))
        return fail(ErrorCode::InvalidArgument, what + ": the rotation is a zero quaternion");
    const ColliderPose pose{translation, rotation / length, s.scene.colliders[collider].scale};
    shared::GpuBody record = s.placedBody(b, pose);
    if (std::optional<Impl::KinematicBody>& held = s.kinematic[b])
        held = Impl::KinematicBody{pose, std::nullopt}; // its poses give its velocity
    else {
        record.linearVelocity = linearVelocity;
        record.angularVelocity = angularVelocity;
    }
    // The record's first 64 bytes are the body's state; the rest is its set-up's.
    static_assert(offsetof(shared::GpuBody, invInertia) == 64);
    s.bodyBuf.upload(&record, 64, std::size_t(b) * sizeof(shared::GpuBody));
    // Its collider record as the body pass would write it, without motion: the jump is no
    // velocity the push-out or friction should see.
    shared::GpuCollider& r = s.colliderRecords[collider];
    r.worldToGrid = glm::inverse(poseMatrix(pose));
    r.boundCentre = record.position;
    r.motion = glm::mat4(1.0f);
    s.colliderBuf.upload(std::span(&r, 1), collider * sizeof(shared::GpuCollider));
    return {};
}

Result<void> Simulation::setBodyKinematic(std::uint32_t collider, bool kinematic) {
    Impl& s = *m_impl;
    auto body = s.bodyOf("setBodyKinematic", collider,
                         "static and kinematic colliders take setColliderPose as they are");
    if (!body)
        return body.error();
    const std::uint32_t b = *body;
    if (s.kinematic[b].has_value() == kinematic)
        return {};
    const std::size_t at = std::size_t(b) * sizeof(shared::GpuBody);
    if (kinematic) {
        // Where the body is now: the GPU's record once every queued step is done.
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        shared::GpuBody record = s.bodyBuf.download<shared::GpuBody>(b, 1).at(0);
        s.kinematic[b] = Impl::KinematicBody{bodyPose(record), std::nullopt};
        const shared::GpuBody held = s.placedBody(b, s.kinematic[b]->at);
        record.invMass = held.invMass;
        record.invInertia = held.invInertia;
        record.kinematic = held.kinematic;
        s.bodyBuf.upload(&record, sizeof record, at);
        return {};
    }
    // Back to the water, at the velocity its last step gave it: only the masses and the flag.
    s.kinematic[b].reset();
    const shared::GpuBody& setUp = s.bodySetup.records[b];
    s.bodyBuf.upload(&setUp.invMass, sizeof setUp.invMass, at + offsetof(shared::GpuBody, invMass));
    s.bodyBuf.upload(&setUp.invInertia, sizeof setUp.invInertia,
                     at + offsetof(shared::GpuBody, invInertia));
    s.bodyBuf.upload(&setUp.kinematic, sizeof setUp.kinematic,
                     at + offsetof(shared::GpuBody, kinematic));
    return {};
}

Result<std::uint32_t> Simulation::Impl::bodyOf(const std::string& call, std::uint32_t collider,
                                               const char* otherwise) const {
    const std::string what = call + ": collider " + std::to_string(collider);
    if (collider >= scene.colliders.size())
        return fail(ErrorCode::InvalidArgument,
                    what + " of " + std::to_string(scene.colliders.size()) + " colliders");
    const std::uint32_t b = bodySetup.bodyOfCollider[collider];
    if (b == shared::kNoBody)
        return fail(ErrorCode::InvalidArgument, what + " is no dynamic body; " + otherwise);
    return b;
}

shared::GpuBody Simulation::Impl::placedBody(std::uint32_t b, const ColliderPose& pose) const {
    shared::GpuBody record = bodySetup.records[b];
    record.orientation =
        glm::vec4(pose.rotation.x, pose.rotation.y, pose.rotation.z, pose.rotation.w);
    record.position = pose.translation + pose.rotation * (record.scale * record.centerLocal);
    record.linearVelocity = glm::vec3(0.0f);
    record.angularVelocity = glm::vec3(0.0f);
    if (kinematic[b]) {
        record.invMass = 0.0f;
        record.invInertia = glm::mat4(0.0f);
        record.kinematic = 1;
    }
    return record;
}

void Simulation::Impl::moveKinematicBodies() {
    const float stepTime = k.dt * float(std::max(1u, scene.simulation.substeps));
    for (std::uint32_t b = 0; b < bodyCount; ++b) {
        std::optional<KinematicBody>& held = kinematic[b];
        if (!held)
            continue;
        const ColliderPose to = held->to.value_or(held->at);
        shared::GpuBody record = placedBody(b, held->at);
        const shared::GpuBody end = placedBody(b, to);
        record.linearVelocity = (end.position - record.position) / stepTime;
        // The turn from `at` to `to` the short way round, as a rotation vector over the step.
        glm::quat turn = to.rotation * glm::conjugate(held->at.rotation);
        if (turn.w < 0.0f)
            turn = -turn;
        const glm::vec3 axis(turn.x, turn.y, turn.z);
        const float sine = glm::length(axis);
        if (sine > 0.0f)
            record.angularVelocity = axis / sine * (2.0f * std::atan2(sine, turn.w) / stepTime);
        bodyBuf.upload(&record, 64, std::size_t(b) * sizeof(shared::GpuBody));
        held = KinematicBody{to, std::nullopt};
    }
}

Result<std::uint32_t> Simulation::addParticles(const std::vector<glm::vec3>& positions,
                                               const std::vector<glm::vec3>& velocities) {
    Impl& s = *m_impl;
    if (!velocities.empty() && velocities.size() != positions.size())
        return fail(ErrorCode::InvalidArgument,
                    "addParticles: " + std::to_string(velocities.size()) + " velocities for " +
                        std::to_string(positions.size()) + " positions");
    if (positions.size() > std::size_t(s.capacity - s.count))
        return fail(ErrorCode::InvalidArgument,
                    "addParticles: " + std::to_string(positions.size()) +
                        " particles do not fit: " + std::to_string(s.count) + " of the capacity " +
                        std::to_string(s.capacity) + " are in use");
    for (std::size_t i = 0; i < positions.size(); ++i)
        if (!finite(positions[i]) || (!velocities.empty() && !finite(velocities[i])))
            return fail(ErrorCode::NonFinite,
                        "addParticles: particle " + std::to_string(i) + " is not finite");
    const std::uint32_t first = s.nextId;
    std::vector<ParticleState> added;
    added.reserve(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i)
        added.push_back(
            {positions[i], velocities.empty() ? glm::vec3(0.0f) : velocities[i], s.nextId++});
    s.append(added);
    return first;
}

Result<void> Simulation::removeParticles(const std::vector<std::uint32_t>& ids) {
    Impl& s = *m_impl;
    std::vector<std::uint32_t> list = s.removeIdList;
    for (std::uint32_t id : ids) {
        if (id >= s.nextId)
            return fail(ErrorCode::InvalidArgument,
                        "removeParticles: id " + std::to_string(id) +
                            " was never given out (the ids so far are 0 to " +
                            std::to_string(s.nextId) + " - 1)");
        list.push_back(id);
    }
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    if (auto ok = s.allocateRemoval(list.size()); !ok)
        return ok;
    if (!list.empty())
        s.removeIdBuf.upload(list);
    s.removeIdList = std::move(list);
    s.removal = s.removal || !s.removeIdList.empty();
    return {};
}

Result<void> Simulation::removeParticlesIn(glm::vec3 min, glm::vec3 max) {
    Impl& s = *m_impl;
    std::vector<format::Drain> boxes = s.drains;
    boxes.insert(boxes.end(), s.removeBoxes.begin(), s.removeBoxes.end());
    boxes.push_back({min, max});
    if (auto ok = format::checkDrains(boxes, "drains and removal boxes"); !ok)
        return fail(ok.error().code, "removeParticlesIn: " + ok.error().detail);
    s.removeBoxes.push_back({min, max});
    s.removal = true;
    return {};
}

Result<void> Simulation::setDrains(const std::vector<format::Drain>& drains) {
    Impl& s = *m_impl;
    std::vector<format::Drain> boxes = drains;
    boxes.insert(boxes.end(), s.removeBoxes.begin(), s.removeBoxes.end());
    if (auto ok = format::checkDrains(boxes, "drains and removal boxes"); !ok)
        return fail(ok.error().code, "setDrains: " + ok.error().detail);
    s.drains = drains;
    s.removal = s.removal || !drains.empty();
    return {};
}

std::uint32_t Simulation::liveParticleCount() const {
    return m_impl->liveNow();
}

const std::vector<format::Drain>& Simulation::drains() const {
    return m_impl->drains;
}

ParticleView Simulation::particleView() const {
    const Impl& s = *m_impl;
    ParticleView view;
    view.positions = s.pos[s.cur].id();
    view.velocities = s.vel[s.cur].id();
    view.ids = s.id[s.cur].id();
    view.count = s.count;
    view.drawArgs = s.drawArgs.id();
    return view;
}

Result<void> Simulation::copyParticlesById(const ParticleCopyTarget& target) {
    Impl& s = *m_impl;
    const ParticleSlots from{&s.pos[s.cur], &s.vel[s.cur], &s.id[s.cur], s.count};
    return s.idOrderCopy.run(from, target);
}

Result<void> Simulation::measureForce(std::uint32_t collider, bool on) {
    Impl& s = *m_impl;
    if (collider >= s.scene.colliders.size())
        return fail(ErrorCode::InvalidArgument, "measureForce: collider " +
                                                    std::to_string(collider) + " of " +
                                                    std::to_string(s.scene.colliders.size()));
    if (s.bodySetup.bodyOfCollider[collider] != shared::kNoBody)
        return fail(ErrorCode::InvalidArgument,
                    "measureForce: collider " + std::to_string(collider) +
                        " is a dynamic body; its force is in latestBodies()");
    if (auto ok = s.forceMeter.set(collider, on, s.colliderDefines()); !ok)
        return ok;
    s.scene.colliders[collider].measureForce = on;
    return {};
}

std::optional<ForcesReading> Simulation::latestForces() const {
    return m_impl->forceMeter.latest();
}

} // namespace sluice::rt
