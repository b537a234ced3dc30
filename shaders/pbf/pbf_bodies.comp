// Dynamic bodies, once per substep after the solve (docs/bodies.md): the fluid's reaction from
// the fixed-point sums, gravity, integration, contacts with the domain box, the static colliders
// and the other bodies, then each body's collider record for the next substep. One work group
// per body; its invocations (lanes) split its contact points, and their corrections are summed
// in a fixed tree, so --deterministic stays byte-identical. Several dispatches make one pass
// (Simulation::Impl::integrateBodies): the start (reaction, gravity, prediction), then one per
// Jacobi sweep of the contacts, the bodies exchanging their poses through `steps`
// (GpuBodyStep); the last sweep finishes. With one body the start and the sweeps share one
// dispatch.
#version 450 core

#define PBF_WITH_COLLIDERS 1
#define PBF_COLLIDERS_WRITABLE 1
#define PBF_WITH_BODIES 1
#include "glsl/PbfGlsl.h"
#include "glsl/FilmGlsl.h"

// Invocations of a body's work group, chosen by Simulation (bodyGroupSize): kBodyLanes on a
// GPU, kBodyLanesSoftware on a software renderer.
#ifndef SLUICE_BODY_LANES
#define SLUICE_BODY_LANES kBodyLanes
#endif
const uint kLanes = SLUICE_BODY_LANES;
layout(local_size_x = SLUICE_BODY_LANES) in;

layout(std430, binding = kBindBodySums) buffer BodySums { uint bodySums[]; };
layout(std430, binding = kBindBodySamples) readonly buffer BodySamples { vec4 samples[]; };
layout(std430, binding = kBindBodySteps) coherent buffer BodySteps { GpuBodyStep steps[]; };
layout(std430, binding = kBindStats) buffer Stats { PbfStats stats; };

// The mouse spring of the viewer (Simulation::setDrag): body dragBody (kNoBody: none) is pulled
// at its point dragAnchor [asset units] towards dragTarget [m] by a critically damped spring of
// angular frequency dragOmega [rad/s], whatever its mass.
uniform uint dragBody;
uniform vec3 dragAnchor;
uniform vec3 dragTarget;
uniform float dragOmega;
// The force and torque a body reports are means over the step's substeps: the first substep
// of a step starts them again, each adds its share.
uniform uint firstSubstep;
uniform float substepShare;
// What this dispatch does: the start when withStart is 1, then the sweeps sweepBegin to
// sweepEnd - 1 of kBodyContactSweeps (the last one finishes the substep).
uniform uint withStart;
uniform uint sweepBegin;
uniform uint sweepEnd;

// Which of the two poses in `steps` holds every body's pose at the current sweep's start.
uint gPoseFrom = 0u;

vec3 posedPosition(uint o) { return steps[o].poses[gPoseFrom].position; }
vec4 posedOrientation(uint o) { return steps[o].poses[gPoseFrom].orientation; }

// Each lane's share of its body's corrections in a sweep, summed over the lanes in a fixed tree:
// (sum of position steps, corrections), (sum of rotation steps, deepest), (sum of normals,
// contacts).
shared vec4 sStep[kLanes];
shared vec4 sTurn[kLanes];
shared vec4 sNormal[kLanes];
// The body's pose as its lead has advanced it in the sweep, and what it may touch in the sweep
// (Reach, packed: wall bits, static mask).
shared vec3 sPosition;
shared vec4 sOrientation;
shared uvec2 sReach;

#include "glsl/BodyContactsGlsl.h"

// One body through the start: its pose at the substep start (x0, q0), its velocity after the
// fluid's reaction, gravity and the drag (v, w), and the fluid's force and torque.
struct BodyStart {
    vec3 x0;
    vec4 q0;
    vec3 v;
    vec3 w;
    vec3 force;
    vec3 torque;
};

// The fluid's reaction: every particle the body pushed by dx gave it -m dx / dt, and the water
// sealed under its contacts as much (sealedDx, sealedMoment); gravity.
void takeFluidReaction(uint b, vec3 sealedDx, vec3 sealedMoment, inout BodyStart s) {
    vec3 sumDx = sumOf(b, kBodySumPush) / bodies[b].sumScale + sealedDx;
    vec3 sumMoment = sumOf(b, kBodySumMoment) / bodies[b].momentScale + sealedMoment;
    vec3 impulse = -P.particleMass * P.invDt * sumDx;
    vec3 angularImpulse = -P.particleMass * P.invDt * sumMoment;
    s.force = impulse * P.invDt;
    s.torque = angularImpulse * P.invDt;
    s.v = bodies[b].linearVelocity + P.dt * P.gravity + impulse * bodies[b].invMass;
    s.w = bodies[b].angularVelocity + worldInvInertia(b, s.q0) * angularImpulse;
}

// An impulse (and its angular impulse) that may only stop the body: the share of it that ends the
// body's approach along it beyond `allowed` [m/s], at the centre or, `atPoint`, where it acts
// (the point of its line of action nearest the centre, with that point's velocity and the body's
// effective mass there). The held particles and the film model's excess go through it.
void takeStopping(uint b, vec3 impulse, vec3 angular, float allowed, bool atPoint,
                  inout BodyStart s) {
    float len = length(impulse);
    if (!(len > 0.0))
        return;
    vec3 n = impulse / len;
    float share;
    if (atPoint) {
        vec3 at = cross(impulse, angular) / (len * len);
        vec3 turn = cross(at, n);
        float invMassAt = bodies[b].invMass + dot(turn, worldInvInertia(b, s.q0) * turn);
        float approach = -dot(s.v + cross(s.w, at), n) - allowed;
        share = approach > 0.0 ? min(1.0, approach / (invMassAt * len)) : 0.0;
    } else {
        float approach = -dot(s.v, n) - allowed;
        share = approach > 0.0 ? min(1.0, approach * bodies[b].mass / len) : 0.0;
    }
    s.v += share * impulse * bodies[b].invMass;
    s.w += share * (worldInvInertia(b, s.q0) * angular);
    s.force += share * impulse * P.invDt;
    s.torque += share * angular * P.invDt;
}

// The particles a wall held against the body: their pushes' reaction only stops the body moving
// into them (along the reaction's direction), like a contact with no bounce; none of it pushes
// the body away (docs/bodies.md). The contact is taken where the held impulse acts (the point of
// its line of action nearest the centre), with that point's velocity and the body's effective
// mass there: taken at the centre, the held impulse's moment spun a body the floor's layer held
// off-centre (docs/bodies.md, "The film under a body").
void takeHeldReaction(uint b, inout BodyStart s) {
    vec3 heldImpulse = -P.particleMass * P.invDt * sumOf(b, kBodySumHeldPush) / bodies[b].sumScale;
    vec3 heldAngular =
        -P.particleMass * P.invDt * sumOf(b, kBodySumHeldMoment) / bodies[b].momentScale;
    takeStopping(b, heldImpulse, heldAngular, 0.0, true, s);
}

// The film model's excess (docs/bodies.md, "The film under a body"): what sealedReaction took
// off the water under the body, as a particle's dx and its moment, is given back only as far as
// it keeps the body from approaching the solid faster than kFilmDrainSpeed: the film drains, but
// no faster than the water can be squeezed out sideways at this resolution.
vec3 gFilmDx = vec3(0.0);
vec3 gFilmMoment = vec3(0.0);

void takeFilmReaction(uint b, inout BodyStart s) {
    takeStopping(b, -P.particleMass * P.invDt * gFilmDx, -P.particleMass * P.invDt * gFilmMoment,
                 kFilmDrainSpeed, false, s);
}

// The viewer's mouse spring, when it holds this body.
void pullByDrag(uint b, inout BodyStart s) {
    if (b != dragBody)
        return;
    vec3 r = rotate(s.q0, bodies[b].scale * (dragAnchor - bodies[b].centerLocal));
    vec3 pointVelocity = s.v + cross(s.w, r);
    vec3 pull = dragOmega * dragOmega * (dragTarget - (s.x0 + r)) - 2.0 * dragOmega * pointVelocity;
    vec3 impulse = bodies[b].mass * P.dt * pull;
    s.v += impulse * bodies[b].invMass;
    s.w += worldInvInertia(b, s.q0) * cross(r, impulse);
}

// The sums start again for the next substep's passes.
void clearSums(uint b) {
    for (uint k = 0u; k < kBodySumWords; ++k)
        bodySums[b * kBodySumWords + k] = 0u;
}

// Velocities from the pose change (position-based), then restitution along the mean contact
// normal for impacts faster than what gravity adds in one substep; the body's record and its
// collider's for the next substep.
// A body's new state is unusable: not finite, or its centre of mass outside the domain box
// (the walls hold its contact points, so only a body the solver lost gets there).
bool bodyFault(vec3 x, vec4 q, vec3 v, vec3 w) {
    bool finite = allFinite(x) && allFinite(q.xyz) && allFinite(vec3(q.w)) && allFinite(v) &&
                  allFinite(w);
    if (!finite)
        return true;
    if (P.hasDomain == 0u)
        return false;
    vec3 lo = P.domainMin - vec3(P.radius), hi = P.domainMax + vec3(P.radius);
    return any(lessThan(x, lo)) || any(greaterThan(x, hi));
}

void finish(uint b, GpuBodyStep work, vec3 x, vec4 q) {
    vec3 x0 = work.startPosition;
    vec4 q0 = work.startOrientation;
    vec3 vNew = (x - x0) * P.invDt;
    vec4 dq = quatMul(q, vec4(-q0.xyz, q0.w));
    vec3 wNew = 2.0 * P.invDt * (dq.w < 0.0 ? -dq.xyz : dq.xyz);
    float nLen = length(work.normalSum);
    if (work.touching > 0u && nLen > 0.0 && bodies[b].restitution > 0.0) {
        vec3 n = work.normalSum / nLen;
        float approach = dot(work.velocity, n);
        if (-approach > 2.0 * length(P.gravity) * P.dt)
            vNew += n * (-bodies[b].restitution * approach - dot(vNew, n));
    }
    if (bodyFault(x, q, vNew, wNew)) {
        // Put back where the substep found it, at rest, and counted (--check fails on it), as
        // a particle that goes non-finite is.
        x = x0;
        q = q0;
        vNew = wNew = vec3(0.0);
        atomicAdd(stats.bodyFaults, 1u);
    }
    GpuBody body = bodies[b];
    body.position = x;
    body.orientation = q;
    body.linearVelocity = vNew;
    body.angularVelocity = wNew;
    body.force = (firstSubstep != 0u ? vec3(0.0) : body.force) + substepShare * work.force;
    body.torque = (firstSubstep != 0u ? vec3(0.0) : body.torque) + substepShare * work.torque;
    body.contactDepth = work.deepest;
    body.contacts = work.touching;
    bodies[b] = body;
    writeCollider(body, x0, q0);
}

// The start, by the body's lead: the fluid's reaction (with the sealed contacts' share, summed
// over the lanes), gravity, the drag, and the predicted pose (poses[0], which the first sweep
// reads).
void startBody(uint b, vec3 sealedDx, vec3 sealedMoment) {
    BodyStart s;
    s.x0 = bodies[b].position;
    s.q0 = bodies[b].orientation;
    takeFluidReaction(b, sealedDx, sealedMoment, s);
    takeFilmReaction(b, s);
    takeHeldReaction(b, s);
    pullByDrag(b, s);
    // A kinematic body moves as the game placed it: at the velocities the CPU set for this step
    // (Simulation::Impl::moveKinematicBodies). What the water gave it is still its force.
    if (bodies[b].kinematic != 0u) {
        s.v = bodies[b].linearVelocity;
        s.w = bodies[b].angularVelocity;
    }
    clearSums(b);
    GpuBodyStep work;
    work.poses[0].position = s.x0 + P.dt * s.v;
    work.poses[0].pad0 = 0.0;
    work.poses[0].orientation = normalize(s.q0 + 0.5 * P.dt * quatMul(vec4(s.w, 0.0), s.q0));
    work.poses[1] = work.poses[0];
    work.startPosition = s.x0;
    work.deepest = 0.0;
    work.startOrientation = s.q0;
    work.velocity = s.v;
    work.touching = 0u;
    work.force = s.force;
    work.pad1 = 0.0;
    work.torque = s.torque;
    work.pad2 = 0.0;
    work.normalSum = vec3(0.0);
    work.pad3 = 0.0;
    steps[b] = work;
}

// The film model (docs/bodies.md, "The film under a body"): the faces over a solid
// within the sealed band get the water's pressure at their depth under the level, rho0 |g|
// (level - y), across the solid, its moment along their own normals, their weight fading out
// over the band's last spacing. Where the water under them gave less, it is topped up;
// where it gave more, its pushes are scaled down to it, force and moment, and what is taken off
// is given back only as far as it holds the body's approach to kFilmDrainSpeed
// (takeFilmReaction). The contact points' areas count at kFilmAreaShare (Bodies.h).
void filmReaction(uint b, uint word, out vec3 sealedDx, out vec3 sealedMoment) {
    vec3 sealed = sStep[0].xyz;
    float sealedLength = length(sealed);
    float head = sStep[0].w; // sum of area * head over every face over a solid in the rim band
    sealedDx = vec3(0.0);
    sealedMoment = vec3(0.0);
    float g = length(P.gravity);
    if (!(sealedLength > 0.0) || !(head > 0.0) || !(g > 0.0) || word == 0u)
        return;
    vec3 along = sealed / sealedLength;
    float weight = min(1.0, sealedLength / head);
    vec3 under = sumOf(b, kBodySumUnder) / bodies[b].sumScale;
    float given = dot(under, along);
    float expected = kFilmAreaShare * g * P.dt * P.dt / PBF_VOLUME * head; // as a sum of dx
    if (given < expected) {
        float add = (expected - given) * weight;
        sealedDx = add * along;
        sealedMoment = add / sealedLength * sTurn[0].xyz;
    } else if (given > expected) {
        float cut = (given - expected) / given * weight;
        sealedDx = -cut * under;
        sealedMoment = -cut * sumOf(b, kBodySumUnderMoment) / bodies[b].momentScale;
        gFilmDx = -sealedDx;
        gFilmMoment = -sealedMoment;
    }
}

// The film model's sums over the body's contact points (sealedShare), each lane's share added
// in a fixed tree (the same order every run); every invocation calls it (barriers), and each
// ends with the film's correction (sealedDx, as a particle's dx) and its moment about the
// centre of mass.
void sealedReaction(uint b, uint lane, out vec3 sealedDx, out vec3 sealedMoment) {
    uint word = bodySums[b * kBodySumWords + kBodySumSurface];
    SealedSums sums = sealedShare(b, lane, kLanes, bodies[b].position, bodies[b].orientation,
                                  surfaceLevel(b, word));
    sStep[lane] = vec4(sums.sealed, sums.head);
    sTurn[lane] = vec4(sums.turn, 0.0);
    memoryBarrierShared();
    barrier();
    for (uint stride = kLanes >> 1; stride > 0u; stride >>= 1) {
        if (lane < stride) {
            sStep[lane] += sStep[lane + stride];
            sTurn[lane] += sTurn[lane + stride];
        }
        memoryBarrierShared();
        barrier();
    }
    filmReaction(b, word, sealedDx, sealedMoment);
}

// The lanes' shares added in a fixed tree (the same order every run); lane 0 ends with the
// totals in sStep[0], sTurn[0] and sNormal[0]. Every invocation calls it (barriers).
void sumLanes(uint lane, ContactSums sums) {
    sStep[lane] = vec4(sums.step, float(sums.count));
    sTurn[lane] = vec4(sums.turn, sums.deepest);
    sNormal[lane] = vec4(sums.normals, float(sums.touching));
    memoryBarrierShared();
    barrier();
    for (uint stride = kLanes >> 1; stride > 0u; stride >>= 1) {
        if (lane < stride) {
            sStep[lane] += sStep[lane + stride];
            sTurn[lane] = vec4(sTurn[lane].xyz + sTurn[lane + stride].xyz,
                               max(sTurn[lane].w, sTurn[lane + stride].w));
            sNormal[lane] += sNormal[lane + stride];
        }
        memoryBarrierShared();
        barrier();
    }
}

// The lead moves the body by the mean of the summed corrections (Jacobi with averaging: every
// contact's correction is computed at the same pose, so the body takes their mean, not their
// sum) and keeps what its contacts touched (counted in the first sweep).
void applySums(bool first, inout vec3 x, inout vec4 q, inout GpuBodyStep work) {
    float contacts = sStep[0].w;
    if (contacts > 0.0) {
        x += sStep[0].xyz / contacts;
        q = normalize(q + 0.5 * quatMul(vec4(sTurn[0].xyz / contacts, 0.0), q));
    }
    if (first) {
        work.deepest = max(work.deepest, sTurn[0].w);
        work.touching += uint(sNormal[0].w);
    }
    work.normalSum += sNormal[0].xyz;
}

// One Jacobi sweep of body b's contacts: against the other bodies at their poses of the sweep's
// start (a pair splits each correction by the bodies' inverse masses; the other body moves its
// share when it tests its own points), then against the walls and static colliders at the pose
// the pairs left, so their friction acts on what the pairs left. Every invocation calls it.
void sweepContacts(uint b, uint lane, uint sweep) {
    bool lead = lane == 0u, first = sweep == 0u;
    gPoseFrom = sweep & 1u;
    vec3 x0 = steps[b].startPosition;
    vec4 q0 = steps[b].startOrientation;
    vec3 x = posedPosition(b);
    vec4 q = posedOrientation(b);
    // A kinematic body takes no correction of its own (its inverse mass is 0): the bodies it
    // meets take all of each, and the walls and static colliders do not stop it.
    bool kinematic = bodies[b].kinematic != 0u; // the same for every lane
    sumLanes(lane, kinematic ? noContacts() : pairShare(b, lane, kLanes, x0, q0, x, q, first));
    GpuBodyStep work;
    if (lead) {
        work = steps[b];
        applySums(first, x, q, work);
        sPosition = x;
        sOrientation = q;
        sReach = packReach(reachOf(b, posedPosition(b), 0.0)); // from the sweep's starting pose
    }
    memoryBarrierShared();
    barrier();
    x = sPosition;
    q = sOrientation;
    sumLanes(lane, kinematic ? noContacts()
                             : wallAndStaticShare(b, unpackReach(sReach), lane, kLanes, x0, q0, x,
                                                  q, first));
    if (lead) {
        applySums(first, x, q, work);
        work.poses[gPoseFrom ^ 1u].position = x;
        work.poses[gPoseFrom ^ 1u].orientation = q;
        steps[b] = work;
        if (sweep + 1u == kBodyContactSweeps)
            finish(b, work, x, q);
    }
    // A next sweep in this dispatch (one body) reads what the lead wrote.
    memoryBarrierBuffer();
    barrier();
}

void main() {
    // One work group per body: the dispatch launches exactly P.bodyCount groups.
    uint b = gl_WorkGroupID.x, lane = gl_LocalInvocationIndex;
    if (withStart != 0u) {
        vec3 sealedDx = vec3(0.0), sealedMoment = vec3(0.0);
        // The film model works where the body has water over it and its sphere, grown by the rim
        // band, reaches a wall or a static collider: elsewhere no contact point lies within the
        // band of a solid (sealedShare would find none). The test is the same for every lane,
        // so the lanes skip the sums and their barriers together.
        bool sealedWork = bodySums[b * kBodySumWords + kBodySumSurface] != 0u &&
                          reachesAnything(reachOf(b, bodies[b].position, rimBand()));
        if (sealedWork)
            sealedReaction(b, lane, sealedDx, sealedMoment);
        memoryBarrierBuffer();
        barrier(); // every lane has read the body's sums before the lead clears them
        if (lane == 0u)
            startBody(b, sealedDx, sealedMoment);
        memoryBarrierBuffer();
        barrier();
    }
    for (uint sweep = sweepBegin; sweep < sweepEnd; ++sweep)
        sweepContacts(b, lane, sweep);
}
