// Dynamic bodies, once per substep after the solve (docs/bodies.md): the fluid's reaction from
// the fixed-point sums, gravity, integration, contacts with the domain box, the static colliders
// and the other bodies, then each body's collider record for the next substep. One work group
// holds every body; each body has the same power-of-two number of invocations (lanes), which
// split its contact points against the other bodies. Lane 0 of a body does the rest.
#version 450 core

#define PBF_WITH_COLLIDERS 1
#define PBF_COLLIDERS_WRITABLE 1
#define PBF_WITH_BODIES 1
#include "shared/PbfGlsl.h"

// Invocations of the work group, chosen by Simulation (bodyGroupSize): kBodyGroupSize on a GPU;
// kBodyLocalSize on a software renderer, which runs a group's invocations one after the other on
// one CPU thread, where idle lanes cost time instead of saving it. SLUICE_BODY_SPLIT_POINTS is 1
// when the group is larger than that: the lanes then split a body's points near the walls too.
#ifndef SLUICE_BODY_GROUP_SIZE
#define SLUICE_BODY_GROUP_SIZE kBodyGroupSize
#define SLUICE_BODY_SPLIT_POINTS 1
#endif
const uint kGroupSize = SLUICE_BODY_GROUP_SIZE;
layout(local_size_x = SLUICE_BODY_GROUP_SIZE) in;

layout(std430, binding = kBindBodySums) buffer BodySums { uint bodySums[]; };
layout(std430, binding = kBindBodySamples) readonly buffer BodySamples { vec4 samples[]; };
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

// Jacobi sweeps over the bodies; inside a sweep each body visits its own points in order.
const uint kContactSweeps = 4u;

// Every body's pose in the current sweep, for the others' contact tests.
shared vec3 sPosition[kBodyLocalSize];
shared vec4 sOrientation[kBodyLocalSize];
// Each invocation's share of its body's corrections against other bodies in a sweep, summed
// over the body's lanes in a fixed tree (so --deterministic stays byte-identical):
// (sum of position steps, corrections), (sum of rotation steps, deepest), (sum of normals,
// contacts); deepest and contacts are counted in the first sweep only.
shared vec4 sPairStep[kGroupSize];
shared vec4 sPairTurn[kGroupSize];
shared vec4 sPairNormal[kGroupSize];
// The contact points near a wall or a static collider, one bit each, for the sequential pass:
// the body's lanes test a chunk of its points at once, its lane 0 then resolves the marked ones
// in order and clears their words.
#if SLUICE_BODY_SPLIT_POINTS
const uint kCandidateWords = 1024u;
shared uint sCandidates[kCandidateWords];
#endif
// What each body may touch in this sweep (Reach, packed by lane 0): wall bits, static mask.
shared uvec2 sReach[kBodyLocalSize];

// Invocations per body: the largest power of two that fits every body into the group.
uint lanesPerBody() {
#if !SLUICE_BODY_SPLIT_POINTS
    // A software renderer runs a group's invocations a SIMD vector at a time: one invocation per
    // body keeps the bodies side by side in one vector.
    return 1u;
#endif
    uint lanes = kGroupSize;
    while (lanes > 1u && lanes * max(P.bodyCount, 1u) > kGroupSize)
        lanes >>= 1;
    return lanes;
}

#include "shared/BodyContactsGlsl.h"

// One body through the pass: its pose at the substep start (x0, q0), the pose and velocity
// being integrated (x, q, v; w the angular velocity before the contacts), the fluid's force and
// torque for the report, and what its contacts touched (counted in the first sweep).
struct BodyStep {
    vec3 x0;
    vec4 q0;
    vec3 x;
    vec4 q;
    vec3 v;
    vec3 w;
    vec3 force;
    vec3 torque;
    float deepest;
    uint touching;
    vec3 normalSum;
};

// The fluid's reaction: every particle the body pushed by dx gave it -m dx / dt; gravity.
void takeFluidReaction(uint b, inout BodyStep s) {
    vec3 sumDx = sumOf(b, kBodySumPush) / bodies[b].sumScale;
    vec3 sumMoment = sumOf(b, kBodySumMoment) / bodies[b].momentScale;
    vec3 impulse = -P.particleMass * P.invDt * sumDx;
    vec3 angularImpulse = -P.particleMass * P.invDt * sumMoment;
    s.force = impulse * P.invDt;
    s.torque = angularImpulse * P.invDt;
    s.v = bodies[b].linearVelocity + P.dt * P.gravity + impulse * bodies[b].invMass;
    s.w = bodies[b].angularVelocity + worldInvInertia(b, s.q0) * angularImpulse;
}

// The particles a wall held against the body: their pushes' reaction only stops the body moving
// into them (along the reaction's direction), like a contact with no bounce; none of it pushes
// the body away (docs/bodies.md).
void takeHeldReaction(uint b, inout BodyStep s) {
    vec3 heldImpulse = -P.particleMass * P.invDt * sumOf(b, kBodySumHeldPush) / bodies[b].sumScale;
    vec3 heldAngular =
        -P.particleMass * P.invDt * sumOf(b, kBodySumHeldMoment) / bodies[b].momentScale;
    float heldLength = length(heldImpulse);
    if (heldLength > 0.0) {
        float approach = -dot(s.v, heldImpulse / heldLength);
        float share = approach > 0.0 ? min(1.0, approach * bodies[b].mass / heldLength) : 0.0;
        s.v += share * heldImpulse * bodies[b].invMass;
        s.w += share * (worldInvInertia(b, s.q0) * heldAngular);
        s.force += share * heldImpulse * P.invDt;
        s.torque += share * heldAngular * P.invDt;
    }
}

// The viewer's mouse spring, when it holds this body.
void pullByDrag(uint b, inout BodyStep s) {
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

// One sweep of the contacts against the other bodies: the lead publishes its pose, each lane
// sums its share of the body's corrections (pairShare), the lanes' sums are added in a fixed tree
// (so --deterministic stays byte-identical), and the lead applies their mean and packs what the
// body may touch next (walls, static colliders). Every invocation calls it (barriers).
void pairContacts(uint b, uint lane, uint lanes, bool live, bool lead, bool first,
                  inout BodyStep s) {
    uint t = gl_LocalInvocationIndex;
    if (lead) {
        sPosition[b] = s.x;
        sOrientation[b] = s.q;
    }
    memoryBarrierShared();
    barrier();
    vec3 stepSum = vec3(0.0), turnSum = vec3(0.0), normals = vec3(0.0);
    uint count = 0u, touched = 0u;
    float deep = 0.0;
    if (live) {
        s.x = sPosition[b];
        s.q = sOrientation[b];
        pairShare(b, lane, lanes, s.x0, s.q0, s.x, s.q, first, stepSum, turnSum, count, deep,
                  touched, normals);
    }
    sPairStep[t] = vec4(stepSum, float(count));
    sPairTurn[t] = vec4(turnSum, deep);
    sPairNormal[t] = vec4(normals, float(touched));
    memoryBarrierShared();
    barrier();
    for (uint stride = lanes >> 1; stride > 0u; stride >>= 1) {
        if (lane < stride) {
            sPairStep[t] += sPairStep[t + stride];
            sPairTurn[t] = vec4(sPairTurn[t].xyz + sPairTurn[t + stride].xyz,
                                max(sPairTurn[t].w, sPairTurn[t + stride].w));
            sPairNormal[t] += sPairNormal[t + stride];
        }
        memoryBarrierShared();
        barrier();
    }
    if (!lead)
        return;
    float pairs = sPairStep[t].w;
    if (pairs > 0.0) {
        s.x += sPairStep[t].xyz / pairs;
        s.q = normalize(s.q + 0.5 * quatMul(vec4(sPairTurn[t].xyz / pairs, 0.0), s.q));
    }
    if (first) {
        s.deepest = max(s.deepest, sPairTurn[t].w);
        s.touching += uint(sPairNormal[t].w);
    }
    s.normalSum += sPairNormal[t].xyz;
    sReach[b] = packReach(reachOf(b, sPosition[b])); // from the sweep's starting pose
}

#if SLUICE_BODY_SPLIT_POINTS
// The candidate words per body and the chunks of points the largest body needs, the same in
// every invocation (the barriers need that); the words start cleared.
void candidateLayout(out uint words, out uint chunks) {
    words = min(kMaxBodySamples / 32u, kCandidateWords / max(P.bodyCount, 1u));
    uint most = 0u;
    for (uint o = 0u; o < P.bodyCount; ++o)
        most = max(most, bodies[o].sampleCount);
    chunks = (most + 32u * words - 1u) / (32u * words);
    for (uint k = gl_LocalInvocationIndex; k < kCandidateWords; k += kGroupSize)
        sCandidates[k] = 0u;
}

// The walls and static colliders, point by point in order from the lead: the lanes first mark, a
// chunk at a time and at the pose the lead has reached, the points within half a spacing of one;
// the lead resolves only those (a point farther off is met in a later sweep or substep). What
// the body's sphere at the sweep's start cannot reach is skipped. Every invocation calls it.
void wallAndStaticContacts(uint b, uint lane, uint lanes, bool live, bool lead, bool first,
                           uint words, uint chunks, inout BodyStep s) {
    for (uint chunk = 0u; chunk < chunks; ++chunk) {
        if (lead) {
            sPosition[b] = s.x;
            sOrientation[b] = s.q;
        }
        memoryBarrierShared();
        barrier();
        Reach r = unpackReach(live ? sReach[b] : uvec2(0u));
        bool reaches = live && reachesAnything(r);
        uint firstPoint = chunk * 32u * words;
        if (reaches) {
            vec3 xc = sPosition[b];
            vec4 qc = sOrientation[b];
            uint endPoint = min(bodies[b].sampleCount, firstPoint + 32u * words);
            for (uint p = firstPoint + lane; p < endPoint; p += lanes) {
                if (nearWallOrStatic(r, xc + rotate(qc, armOf(b, p)), PBF_RADIUS)) {
                    uint bit = p - firstPoint;
                    atomicOr(sCandidates[b * words + bit / 32u], 1u << (bit % 32u));
                }
            }
        }
        memoryBarrierShared();
        barrier();
        if (lead && reaches) {
            for (uint k = 0u; k < words; ++k) {
                uint bits = sCandidates[b * words + k];
                sCandidates[b * words + k] = 0u;
                while (bits != 0u) {
                    uint bit = uint(findLSB(bits));
                    bits &= bits - 1u;
                    wallsAndStatics(b, r, firstPoint + 32u * k + bit, s.x0, s.q0, s.x, s.q, first,
                                    s.deepest, s.touching, s.normalSum);
                }
            }
        }
    }
}
#else
// On a software renderer the lanes run in turn: the lead visits every point itself.
void wallAndStaticContacts(uint b, bool lead, bool first, inout BodyStep s) {
    if (!lead)
        return;
    Reach r = unpackReach(sReach[b]);
    if (reachesAnything(r))
        for (uint p = 0u; p < bodies[b].sampleCount; ++p)
            wallsAndStatics(b, r, p, s.x0, s.q0, s.x, s.q, first, s.deepest, s.touching,
                            s.normalSum);
}
#endif

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

void finish(uint b, BodyStep s) {
    vec3 vNew = (s.x - s.x0) * P.invDt;
    vec4 dq = quatMul(s.q, vec4(-s.q0.xyz, s.q0.w));
    vec3 wNew = 2.0 * P.invDt * (dq.w < 0.0 ? -dq.xyz : dq.xyz);
    float nLen = length(s.normalSum);
    if (s.touching > 0u && nLen > 0.0 && bodies[b].restitution > 0.0) {
        vec3 n = s.normalSum / nLen;
        float approach = dot(s.v, n);
        if (-approach > 2.0 * length(P.gravity) * P.dt)
            vNew += n * (-bodies[b].restitution * approach - dot(vNew, n));
    }
    if (bodyFault(s.x, s.q, vNew, wNew)) {
        // Put back where the substep found it, at rest, and counted (--check fails on it), as
        // a particle that goes non-finite is.
        s.x = s.x0;
        s.q = s.q0;
        vNew = wNew = vec3(0.0);
        atomicAdd(stats.bodyFaults, 1u);
    }
    GpuBody body = bodies[b];
    body.position = s.x;
    body.orientation = s.q;
    body.linearVelocity = vNew;
    body.angularVelocity = wNew;
    body.force = (firstSubstep != 0u ? vec3(0.0) : body.force) + substepShare * s.force;
    body.torque = (firstSubstep != 0u ? vec3(0.0) : body.torque) + substepShare * s.torque;
    body.contactDepth = s.deepest;
    body.contacts = s.touching;
    bodies[b] = body;
    writeCollider(body, s.x0, s.q0);
}

void main() {
    uint lanes = lanesPerBody();
    uint b = gl_LocalInvocationIndex / lanes, lane = gl_LocalInvocationIndex % lanes;
    bool live = b < P.bodyCount;
    bool lead = live && lane == 0u;
    BodyStep s;
    s.x0 = live ? bodies[b].position : vec3(0.0);
    s.q0 = live ? bodies[b].orientation : vec4(0.0, 0.0, 0.0, 1.0);
    s.x = vec3(0.0);
    s.q = s.q0;
    s.v = s.w = s.force = s.torque = s.normalSum = vec3(0.0);
    s.deepest = 0.0;
    s.touching = 0u;
    if (lead) {
        takeFluidReaction(b, s);
        takeHeldReaction(b, s);
        pullByDrag(b, s);
        clearSums(b);
        s.x = s.x0 + P.dt * s.v;
        s.q = normalize(s.q0 + 0.5 * P.dt * quatMul(vec4(s.w, 0.0), s.q0));
    }
#if SLUICE_BODY_SPLIT_POINTS
    uint words, chunks;
    candidateLayout(words, chunks);
#endif
    for (uint sweep = 0u; sweep < kContactSweeps; ++sweep) {
        bool first = sweep == 0u;
        pairContacts(b, lane, lanes, live, lead, first, s);
#if SLUICE_BODY_SPLIT_POINTS
        wallAndStaticContacts(b, lane, lanes, live, lead, first, words, chunks, s);
#else
        wallAndStaticContacts(b, lead, first, s);
#endif
        memoryBarrierShared();
        barrier();
    }
    if (lead)
        finish(b, s);
}
