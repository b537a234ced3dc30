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
// 64 on a software renderer, which runs a group's invocations one after the other on one CPU
// thread, where idle lanes cost time instead of saving it.
#ifndef SLUICE_BODY_GROUP_SIZE
#define SLUICE_BODY_GROUP_SIZE 512
#endif
const uint kGroupSize = SLUICE_BODY_GROUP_SIZE;
layout(local_size_x = SLUICE_BODY_GROUP_SIZE) in;

layout(std430, binding = kBindBodySums) buffer BodySums { uint bodySums[]; };
layout(std430, binding = kBindBodySamples) readonly buffer BodySamples { vec4 samples[]; };

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
#if SLUICE_BODY_GROUP_SIZE > 64
const uint kCandidateWords = 1024u;
shared uint sCandidates[kCandidateWords];
#endif
// What each body may touch in this sweep (Reach, packed by lane 0): wall bits, static mask.
shared uvec2 sReach[kBodyLocalSize];

// Invocations per body: the largest power of two that fits every body into the group.
uint lanesPerBody() {
#if SLUICE_BODY_GROUP_SIZE <= 64
    // A software renderer runs a group's invocations a SIMD vector at a time: one invocation per
    // body keeps the bodies side by side in one vector.
    return 1u;
#endif
    uint lanes = kGroupSize;
    while (lanes > 1u && lanes * max(P.bodyCount, 1u) > kGroupSize)
        lanes >>= 1;
    return lanes;
}

vec4 quatMul(vec4 a, vec4 b) {
    return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

vec3 rotate(vec4 q, vec3 v) {
    vec3 t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

mat3 rotationOf(vec4 q) {
    return mat3(rotate(q, vec3(1.0, 0.0, 0.0)), rotate(q, vec3(0.0, 1.0, 0.0)),
                rotate(q, vec3(0.0, 0.0, 1.0)));
}

// World inverse inertia R I^-1 R^T of body o at orientation q.
mat3 worldInvInertia(uint o, vec4 q) {
    mat3 r = rotationOf(q);
    return r * mat3(bodies[o].invInertia) * transpose(r);
}

// The 64-bit two's-complement sum in words (lo, lo + 1), as a double.
double sumAt(uint lo) {
    uint hi = bodySums[lo + 1u];
    double high = hi >= 0x80000000u ? double(hi) - 4294967296.0 : double(hi);
    return high * 4294967296.0 + double(bodySums[lo]);
}

// Three consecutive 64-bit sums from word lo: a vector's x, y and z.
vec3 sum3At(uint lo) {
    return vec3(sumAt(lo), sumAt(lo + 2u), sumAt(lo + 4u));
}

// Body b's contact point s relative to its centre of mass, in the asset's axes at world scale.
vec3 armOf(uint b, uint s) {
    return bodies[b].scale * (samples[bodies[b].sampleOffset + s].xyz - bodies[b].centerLocal);
}

// How far world point w lies beyond the wall below and the wall above on axis a: the domain's
// walls sit one particle radius beyond the box particles are kept in.
vec2 wallDepths(int a, vec3 w) {
    return vec2((P.domainMin[a] - PBF_RADIUS) - w[a], w[a] - (P.domainMax[a] + PBF_RADIUS));
}

// Generalised inverse mass of body o at arm r along direction n (Mueller et al. 2020, eq. 2).
float inverseMassAt(uint o, mat3 invI, vec3 r, vec3 n) {
    vec3 rn = cross(r, n);
    return bodies[o].invMass + dot(rn, invI * rn);
}

// The correction `resolve` would make, without making it: the position step and the rotation
// step (the quaternion increment's vector part, to be applied as q += (turn, 0) q / 2).
void correction(uint b, vec3 x, vec4 q, vec3 arm, vec3 pStart, vec3 n, float depth, float share,
                out vec3 dx, out vec3 turn) {
    mat3 invI = worldInvInertia(b, q);
    vec3 r = rotate(q, arm);
    float dn = share * depth / inverseMassAt(b, invI, r, n);
    vec3 p = dn * n;
    vec3 slip = (x + r) - pStart;
    slip -= dot(slip, n) * n;
    float slipLength = length(slip);
    if (slipLength > 0.0) {
        vec3 t = slip / slipLength;
        float dtan = min(share * slipLength / inverseMassAt(b, invI, r, t), bodies[b].friction * dn);
        p -= dtan * t;
    }
    dx = p * bodies[b].invMass;
    turn = invI * cross(r, p);
}

// One contact of body b resolved at once (Gauss-Seidel): its point at arm r (world) from the
// centre is `depth` inside something whose surface normal there is n; `share` of the correction
// is the body's. Pushes out along n and, within the Coulomb cone, removes the point's tangential
// motion since the substep start (slip); position-level, so velocities follow from the pose.
void resolve(uint b, inout vec3 x, inout vec4 q, vec3 arm, vec3 pStart, vec3 n, float depth,
             float share) {
    vec3 dx, turn;
    correction(b, x, q, arm, pStart, n, depth, share, dx, turn);
    x += dx;
    q = normalize(q + 0.5 * quatMul(vec4(turn, 0.0), q));
}

// phi [m] and outward normal of body o, posed at (sPosition[o], sOrientation[o]), at world w.
float bodyDistance(uint o, vec3 w, out vec3 normal) {
    vec4 qo = sOrientation[o];
    float s = bodies[o].scale;
    vec3 local = rotate(vec4(-qo.xyz, qo.w), w - sPosition[o]) / s + bodies[o].centerLocal;
    float phi;
    vec3 grad;
    sampleCollider(bodies[o].collider, local, phi, grad);
    normal = rotate(qo, grad);
    return s * phi;
}

// Whether a static collider can touch body b (centre x, bounding radius reach): false when the
// centre lies inside the collider's grid box, where phi is the interpolated distance, and phi
// there exceeds the reach. Outside the box phi may overestimate, so every point is tested.
bool mayTouch(uint c, vec3 x, float reach) {
    vec3 q = (colliders[c].worldToGrid * vec4(x, 1.0)).xyz;
    if (any(lessThan(q, colliders[c].origin)) || any(greaterThan(q, colliders[c].boxMax)))
        return true;
    vec3 n;
    return colliderDistance(c, x, n) <= reach;
}

// Lane `lane` of `lanes`'s share of body b's corrections against the other bodies in one
// sweep: its points lane, lane + lanes, ... tested against the bodies whose bounding spheres
// meet this one's, at their poses of this sweep's start. The corrections are summed, not
// applied: the sweep averages them over all the body's points (sPairStep).
void pairShare(uint b, uint lane, uint lanes, vec3 x0, vec4 q0, vec3 x, vec4 q, bool first,
               out vec3 stepSum, out vec3 turnSum, out uint count, out float deepest,
               out uint touching, out vec3 normalSum) {
    stepSum = vec3(0.0);
    turnSum = vec3(0.0);
    normalSum = vec3(0.0);
    count = 0u;
    touching = 0u;
    deepest = 0.0;
    GpuBody body = bodies[b];
    float reach = body.boundRadius;
    uint bodyMask = 0u, bodyMaskHigh = 0u; // bit o: body o's sphere meets this one's
    for (uint o = 0u; o < P.bodyCount; ++o) {
        vec3 d = sPosition[o] - x;
        float r = reach + bodies[o].boundRadius;
        if (o != b && dot(d, d) < r * r) {
            if (o < 32u)
                bodyMask |= 1u << o;
            else
                bodyMaskHigh |= 1u << (o - 32u);
        }
    }
    if (bodyMask == 0u && bodyMaskHigh == 0u)
        return;
    mat3 invI = worldInvInertia(b, q);
    for (uint s = lane; s < body.sampleCount; s += lanes) {
        vec3 arm = armOf(b, s);
        vec3 pStart = x0 + rotate(q0, arm);
        vec3 w = x + rotate(q, arm);
        for (uint o = 0u; o < P.bodyCount; ++o) {
            bool near = o < 32u ? (bodyMask & (1u << o)) != 0u
                                : (bodyMaskHigh & (1u << (o - 32u))) != 0u;
            if (!near)
                continue;
            vec3 toOther = w - sPosition[o];
            if (dot(toOther, toOther) >= bodies[o].boundRadius * bodies[o].boundRadius)
                continue;
            vec3 n;
            float phi = bodyDistance(o, w, n);
            float len = length(n);
            if (!(phi < 0.0) || !(len > 0.0))
                continue;
            n /= len;
            // The pair splits the correction by their inverse masses at the point; the other
            // body moves its share when it tests its own points against this one.
            float mine = inverseMassAt(b, invI, w - x, n);
            float theirs = inverseMassAt(o, worldInvInertia(o, sOrientation[o]), toOther, n);
            if (first) {
                deepest = max(deepest, -phi);
                ++touching;
            }
            normalSum += n;
            // Against another body the corrections of the sweep are averaged, not chained:
            // each point would otherwise see the depth the previous one left and take its
            // share of that again, and both bodies together would move the whole depth each.
            vec3 dx, turn;
            correction(b, x, q, arm, pStart, n, -phi, mine / (mine + theirs), dx, turn);
            stepSum += dx;
            turnSum += turn;
            ++count;
        }
    }
}

// What body b's bounding sphere, centred at `xStart`, may touch in this sweep: the domain's
// walls below and above on each axis, and the static colliders (bit c; beyond 32 always).
struct Reach {
    bvec3 wallLo;
    bvec3 wallHi;
    uint staticMask;
};

Reach reachOf(uint b, vec3 xStart) {
    Reach r;
    float reach = bodies[b].boundRadius;
    r.wallLo = bvec3(false);
    r.wallHi = bvec3(false);
    if (P.hasDomain != 0u) {
        r.wallLo = lessThan(xStart - reach, P.domainMin - PBF_RADIUS);
        r.wallHi = greaterThan(xStart + reach, P.domainMax + PBF_RADIUS);
    }
    r.staticMask = 0u;
    for (uint c = 0u; c < min(P.colliderCount, 32u); ++c)
        if (colliders[c].body == kNoBody && mayTouch(c, xStart, reach))
            r.staticMask |= 1u << c;
    return r;
}

uvec2 packReach(Reach r) {
    uvec3 lo = uvec3(r.wallLo), hi = uvec3(r.wallHi);
    return uvec2(lo.x | lo.y << 1 | lo.z << 2 | hi.x << 3 | hi.y << 4 | hi.z << 5, r.staticMask);
}

Reach unpackReach(uvec2 bits) {
    Reach r;
    r.wallLo = notEqual(uvec3(bits.x) & uvec3(1u, 2u, 4u), uvec3(0u));
    r.wallHi = notEqual(uvec3(bits.x) & uvec3(8u, 16u, 32u), uvec3(0u));
    r.staticMask = bits.y;
    return r;
}

bool reachesAnything(Reach r) {
    return any(r.wallLo) || any(r.wallHi) || r.staticMask != 0u || P.colliderCount > 32u;
}

bool staticInReach(Reach r, uint c) {
    return colliders[c].body == kNoBody && (c >= 32u || (r.staticMask & (1u << c)) != 0u);
}

// Whether body b's contact point at world w is within `margin` of a wall or a static collider
// it may touch: the points the sequential pass below visits.
bool nearWallOrStatic(Reach r, vec3 w, float margin) {
    for (int a = 0; a < 3; ++a) {
        vec2 beyond = wallDepths(a, w);
        if ((r.wallLo[a] && beyond.x > -margin) || (r.wallHi[a] && beyond.y > -margin))
            return true;
    }
    for (uint c = 0u; c < P.colliderCount; ++c) {
        if (!staticInReach(r, c))
            continue;
        vec3 n;
        if (colliderDistance(c, w, n) < margin)
            return true;
    }
    return false;
}

// Body b's contact point s against the domain box and the static colliders, resolved at once
// (Gauss-Seidel), so their friction acts on what the pairs left.
void wallsAndStatics(uint b, Reach r, uint s, vec3 x0, vec4 q0, inout vec3 x, inout vec4 q,
                     bool first, inout float deepest, inout uint touching,
                     inout vec3 normalSum) {
    vec3 arm = armOf(b, s);
    vec3 pStart = x0 + rotate(q0, arm);
    for (int a = 0; a < 3; ++a) {
        if (!r.wallLo[a] && !r.wallHi[a])
            continue;
        vec2 beyond = wallDepths(a, x + rotate(q, arm));
        float below = beyond.x, above = beyond.y;
        vec3 axis = vec3(0.0);
        axis[a] = 1.0;
        if (below > 0.0 || above > 0.0) {
            float depth = max(below, above);
            vec3 n = below > 0.0 ? axis : -axis;
            if (first) {
                deepest = max(deepest, depth);
                ++touching;
            }
            normalSum += n;
            resolve(b, x, q, arm, pStart, n, depth, 1.0);
        }
    }
    for (uint c = 0u; c < P.colliderCount; ++c) {
        if (!staticInReach(r, c))
            continue;
        vec3 w = x + rotate(q, arm);
        vec3 n;
        float phi = colliderDistance(c, w, n);
        float len = length(n);
        if (!(phi < 0.0) || !(len > 0.0))
            continue;
        if (first) {
            deepest = max(deepest, -phi);
            ++touching;
        }
        normalSum += n / len;
        resolve(b, x, q, arm, pStart, n / len, -phi, 1.0);
    }
}

// Collider record of body b at its new pose, with `motion` from its pose at the substep start.
void writeCollider(GpuBody body, vec3 x0, vec4 q0) {
    float s = body.scale;
    mat3 r = rotationOf(body.orientation);
    vec3 t = body.position - r * (s * body.centerLocal);
    mat3 inv = transpose(r) / s;
    mat4 toGrid = mat4(vec4(inv[0], 0.0), vec4(inv[1], 0.0), vec4(inv[2], 0.0),
                       vec4(-(inv * t), 1.0));
    mat3 r0 = rotationOf(q0);
    vec3 t0 = x0 - r0 * (s * body.centerLocal);
    mat4 before = mat4(vec4(s * r0[0], 0.0), vec4(s * r0[1], 0.0), vec4(s * r0[2], 0.0),
                       vec4(t0, 1.0));
    uint c = body.collider;
    colliders[c].worldToGrid = toGrid;
    colliders[c].rotation = mat4(r);
    colliders[c].motion = before * toGrid;
    colliders[c].scale = s;
}

void main() {
    uint t = gl_LocalInvocationIndex;
    uint lanes = lanesPerBody();
    uint b = t / lanes, lane = t % lanes;
    bool live = b < P.bodyCount;
    bool lead = live && lane == 0u;
    vec3 x0 = vec3(0.0), x = vec3(0.0), v = vec3(0.0), force = vec3(0.0), torque = vec3(0.0);
    vec4 q0 = vec4(0.0, 0.0, 0.0, 1.0), q = q0;
    if (live) {
        x0 = bodies[b].position;
        q0 = bodies[b].orientation;
    }
    if (lead) {
        // The fluid's reaction: every particle the body pushed by dx gave it -m dx / dt.
        uint base = b * kBodySumWords;
        vec3 sumDx = sum3At(base) / bodies[b].sumScale;
        vec3 sumMoment = sum3At(base + 6u) / bodies[b].momentScale;
        vec3 impulse = -P.particleMass * P.invDt * sumDx;
        vec3 angularImpulse = -P.particleMass * P.invDt * sumMoment;
        force = impulse * P.invDt;
        torque = angularImpulse * P.invDt;

        v = bodies[b].linearVelocity + P.dt * P.gravity + impulse * bodies[b].invMass;
        vec3 w = bodies[b].angularVelocity + worldInvInertia(b, q0) * angularImpulse;
        // The particles a wall held against the body: their pushes' reaction only stops the
        // body moving into them (along the reaction's direction), like a contact with no
        // bounce; none of it pushes the body away (docs/bodies.md).
        uint held = base + kBodyHeldWords;
        vec3 heldImpulse = -P.particleMass * P.invDt * sum3At(held) / bodies[b].sumScale;
        vec3 heldAngular = -P.particleMass * P.invDt * sum3At(held + 6u) / bodies[b].momentScale;
        float heldLength = length(heldImpulse);
        if (heldLength > 0.0) {
            float approach = -dot(v, heldImpulse / heldLength);
            float share = approach > 0.0 ? min(1.0, approach * bodies[b].mass / heldLength) : 0.0;
            v += share * heldImpulse * bodies[b].invMass;
            w += share * (worldInvInertia(b, q0) * heldAngular);
            force += share * heldImpulse * P.invDt;
            torque += share * heldAngular * P.invDt;
        }
        if (b == dragBody) {
            vec3 r = rotate(q0, bodies[b].scale * (dragAnchor - bodies[b].centerLocal));
            vec3 pointVelocity = v + cross(w, r);
            vec3 pull = dragOmega * dragOmega * (dragTarget - (x0 + r)) -
                        2.0 * dragOmega * pointVelocity;
            vec3 impulse = bodies[b].mass * P.dt * pull;
            v += impulse * bodies[b].invMass;
            w += worldInvInertia(b, q0) * cross(r, impulse);
        }
        for (uint k = 0u; k < kBodySumWords; ++k)
            bodySums[base + k] = 0u;
        x = x0 + P.dt * v;
        q = normalize(q0 + 0.5 * P.dt * quatMul(vec4(w, 0.0), q0));
    }

    float deepest = 0.0;
    uint touching = 0u;
    vec3 normalSum = vec3(0.0);
#if SLUICE_BODY_GROUP_SIZE > 64
    // Candidate words per body, and the chunks of points the largest body needs: the same in
    // every invocation, as the barriers need.
    uint words = min(kMaxBodySamples / 32u, kCandidateWords / max(P.bodyCount, 1u));
    uint most = 0u;
    for (uint o = 0u; o < P.bodyCount; ++o)
        most = max(most, bodies[o].sampleCount);
    uint chunks = (most + 32u * words - 1u) / (32u * words);
    for (uint k = t; k < kCandidateWords; k += kGroupSize)
        sCandidates[k] = 0u;
#endif
    for (uint it = 0u; it < kContactSweeps; ++it) {
        bool first = it == 0u;
        if (lead) {
            sPosition[b] = x;
            sOrientation[b] = q;
        }
        memoryBarrierShared();
        barrier();
        vec3 stepSum = vec3(0.0), turnSum = vec3(0.0), normals = vec3(0.0);
        uint count = 0u, touched = 0u;
        float deep = 0.0;
        if (live) {
            x = sPosition[b];
            q = sOrientation[b];
            pairShare(b, lane, lanes, x0, q0, x, q, first, stepSum, turnSum, count, deep,
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
        if (lead) {
            float pairs = sPairStep[t].w;
            if (pairs > 0.0) {
                x += sPairStep[t].xyz / pairs;
                q = normalize(q + 0.5 * quatMul(vec4(sPairTurn[t].xyz / pairs, 0.0), q));
            }
            if (first) {
                deepest = max(deepest, sPairTurn[t].w);
                touching += uint(sPairNormal[t].w);
            }
            normalSum += sPairNormal[t].xyz;
            sReach[b] = packReach(reachOf(b, sPosition[b])); // from the sweep's starting pose
        }
        // Then the walls and static colliders, point by point in order from lane 0. The lanes
        // first mark, a chunk at a time and at the pose lane 0 has reached, the points within
        // half a spacing of one; lane 0 resolves only those (a point farther off is met in a
        // later sweep or substep). What the body's sphere at the sweep's start cannot reach is
        // skipped.
#if SLUICE_BODY_GROUP_SIZE <= 64
        // A software renderer runs the lanes in turn: lane 0 visits every point itself.
        if (lead) {
            Reach r = unpackReach(sReach[b]);
            if (reachesAnything(r))
                for (uint s = 0u; s < bodies[b].sampleCount; ++s)
                    wallsAndStatics(b, r, s, x0, q0, x, q, first, deepest, touching, normalSum);
        }
#else
        for (uint chunk = 0u; chunk < chunks; ++chunk) {
            if (lead) {
                sPosition[b] = x;
                sOrientation[b] = q;
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
                for (uint s = firstPoint + lane; s < endPoint; s += lanes) {
                    if (nearWallOrStatic(r, xc + rotate(qc, armOf(b, s)), PBF_RADIUS)) {
                        uint bit = s - firstPoint;
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
                        wallsAndStatics(b, r, firstPoint + 32u * k + bit, x0, q0, x, q, first,
                                        deepest, touching, normalSum);
                    }
                }
            }
        }
#endif
        memoryBarrierShared();
        barrier();
    }
    if (!lead)
        return;

    // Velocities from the pose change (position-based), then restitution along the mean
    // contact normal for impacts faster than what gravity adds in one substep.
    vec3 vNew = (x - x0) * P.invDt;
    vec4 dq = quatMul(q, vec4(-q0.xyz, q0.w));
    vec3 wNew = 2.0 * P.invDt * (dq.w < 0.0 ? -dq.xyz : dq.xyz);
    float nLen = length(normalSum);
    if (touching > 0u && nLen > 0.0 && bodies[b].restitution > 0.0) {
        vec3 n = normalSum / nLen;
        float approach = dot(v, n);
        if (-approach > 2.0 * length(P.gravity) * P.dt)
            vNew += n * (-bodies[b].restitution * approach - dot(vNew, n));
    }

    GpuBody body = bodies[b];
    body.position = x;
    body.orientation = q;
    body.linearVelocity = vNew;
    body.angularVelocity = wNew;
    body.force = (firstSubstep != 0u ? vec3(0.0) : body.force) + substepShare * force;
    body.torque = (firstSubstep != 0u ? vec3(0.0) : body.torque) + substepShare * torque;
    body.contactDepth = deepest;
    body.contacts = touching;
    bodies[b] = body;
    writeCollider(body, x0, q0);
}
