// Dynamic bodies, once per substep after the solve (docs/bodies.md): the fluid's reaction from
// the fixed-point sums, gravity, integration, contacts with the domain box, the static colliders
// and the other bodies, then each body's collider record for the next substep. One work group
// holds every body.
#version 450 core

#define PBF_WITH_COLLIDERS 1
#define PBF_COLLIDERS_WRITABLE 1
#define PBF_WITH_BODIES 1
#include "shared/PbfGlsl.h"

layout(local_size_x = kBodyLocalSize) in;

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

// One sweep of body b's contact points against the domain box, the static colliders and the
// other bodies' poses of this sweep. What the body's bounding sphere cannot reach is skipped.
void sweep(uint b, vec3 x0, vec4 q0, inout vec3 x, inout vec4 q, bool first,
           inout float deepest, inout uint touching, inout vec3 normalSum) {
    GpuBody body = bodies[b];
    float reach = body.boundRadius;
    // What this sweep tests, decided once from the pose at its start (a sweep moves the body
    // by a small fraction of its size).
    bvec3 wallLo = bvec3(false), wallHi = bvec3(false);
    if (P.hasDomain != 0u) {
        wallLo = lessThan(x - reach, P.domainMin - PBF_RADIUS);
        wallHi = greaterThan(x + reach, P.domainMax + PBF_RADIUS);
    }
    uint staticMask = 0u; // bit c: static collider c may touch (colliders beyond 32 always)
    for (uint c = 0u; c < min(P.colliderCount, 32u); ++c)
        if (colliders[c].body == kNoBody && mayTouch(c, x, reach))
            staticMask |= 1u << c;
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
    bool anyWall = any(wallLo) || any(wallHi);
    vec3 pairDx = vec3(0.0), pairTurn = vec3(0.0);
    uint pairCount = 0u;
    if (!anyWall && staticMask == 0u && P.colliderCount <= 32u && bodyMask == 0u &&
        bodyMaskHigh == 0u)
        return;

    // Other bodies first, from the pose at the sweep's start, their corrections averaged;
    // then the walls and static colliders point by point, so their friction acts on what the
    // pairs left.
    if (bodyMask != 0u || bodyMaskHigh != 0u) {
        for (uint s = 0u; s < body.sampleCount; ++s) {
            vec3 arm = body.scale * (samples[body.sampleOffset + s].xyz - body.centerLocal);
            vec3 pStart = x0 + rotate(q0, arm);
            for (uint o = 0u; o < P.bodyCount; ++o) {
                bool near = o < 32u ? (bodyMask & (1u << o)) != 0u
                                    : (bodyMaskHigh & (1u << (o - 32u))) != 0u;
                if (!near)
                    continue;
                vec3 w = x + rotate(q, arm);
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
                float mine = inverseMassAt(b, worldInvInertia(b, q), w - x, n);
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
                pairDx += dx;
                pairTurn += turn;
                ++pairCount;
            }
        }
        if (pairCount > 0u) {
            x += pairDx / float(pairCount);
            q = normalize(q + 0.5 * quatMul(vec4(pairTurn / float(pairCount), 0.0), q));
        }
    }
    for (uint s = 0u; s < body.sampleCount; ++s) {
        vec3 arm = body.scale * (samples[body.sampleOffset + s].xyz - body.centerLocal);
        vec3 pStart = x0 + rotate(q0, arm);
        // The domain's walls sit one particle radius beyond the box particles are kept in.
        if (anyWall) {
            for (int a = 0; a < 3; ++a) {
                if (!wallLo[a] && !wallHi[a])
                    continue;
                vec3 w = x + rotate(q, arm);
                float below = (P.domainMin[a] - PBF_RADIUS) - w[a];
                float above = w[a] - (P.domainMax[a] + PBF_RADIUS);
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
        }
        for (uint c = 0u; c < P.colliderCount; ++c) {
            if (colliders[c].body != kNoBody || (c < 32u && (staticMask & (1u << c)) == 0u))
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
    uint b = gl_LocalInvocationID.x;
    bool live = b < P.bodyCount;
    vec3 x0 = vec3(0.0), x = vec3(0.0), v = vec3(0.0), force = vec3(0.0), torque = vec3(0.0);
    vec4 q0 = vec4(0.0, 0.0, 0.0, 1.0), q = q0;
    if (live) {
        // The fluid's reaction: every particle the body pushed by dx gave it -m dx / dt.
        uint base = b * kBodySumWords;
        vec3 sumDx = vec3(sumAt(base), sumAt(base + 2u), sumAt(base + 4u)) / bodies[b].sumScale;
        vec3 sumMoment =
            vec3(sumAt(base + 6u), sumAt(base + 8u), sumAt(base + 10u)) / bodies[b].momentScale;
        for (uint k = 0u; k < kBodySumWords; ++k)
            bodySums[base + k] = 0u;
        vec3 impulse = -P.particleMass * P.invDt * sumDx;
        vec3 angularImpulse = -P.particleMass * P.invDt * sumMoment;
        force = impulse * P.invDt;
        torque = angularImpulse * P.invDt;

        x0 = bodies[b].position;
        q0 = bodies[b].orientation;
        v = bodies[b].linearVelocity + P.dt * P.gravity + impulse * bodies[b].invMass;
        vec3 w = bodies[b].angularVelocity + worldInvInertia(b, q0) * angularImpulse;
        if (b == dragBody) {
            vec3 r = rotate(q0, bodies[b].scale * (dragAnchor - bodies[b].centerLocal));
            vec3 pointVelocity = v + cross(w, r);
            vec3 pull = dragOmega * dragOmega * (dragTarget - (x0 + r)) -
                        2.0 * dragOmega * pointVelocity;
            vec3 impulse = bodies[b].mass * P.dt * pull;
            v += impulse * bodies[b].invMass;
            w += worldInvInertia(b, q0) * cross(r, impulse);
        }
        x = x0 + P.dt * v;
        q = normalize(q0 + 0.5 * P.dt * quatMul(vec4(w, 0.0), q0));
    }

    float deepest = 0.0;
    uint touching = 0u;
    vec3 normalSum = vec3(0.0);
    for (uint it = 0u; it < kContactSweeps; ++it) {
        if (live) {
            sPosition[b] = x;
            sOrientation[b] = q;
        }
        memoryBarrierShared();
        barrier();
        if (live)
            sweep(b, x0, q0, x, q, it == 0u, deepest, touching, normalSum);
        memoryBarrierShared();
        barrier();
    }
    if (!live)
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
