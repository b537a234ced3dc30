// GLSL only: the rigid-body math and the contact tests of the body pass (pbf_bodies.comp,
// docs/bodies.md): quaternions, inertia, a contact's correction (Mueller et al. 2020), the
// shares of a body's corrections against the other bodies and against the walls and static
// colliders. Include it after the pass's declarations it reads: the body records and colliders
// (PBF_WITH_BODIES, PBF_WITH_COLLIDERS, glsl/PbfGlsl.h), the contact points `samples`, the
// reaction sums `bodySums`, and every body's pose at the sweep's start, `posedPosition(o)` and
// `posedOrientation(o)`.
#ifndef SLUICE_SHARED_BODY_CONTACTS_GLSL_H
#define SLUICE_SHARED_BODY_CONTACTS_GLSL_H

#ifndef __cplusplus

#include "glsl/BodySumsGlsl.h"

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

// phi [m] and outward normal of body o, at its pose of the sweep's start, at world w.
float bodyDistance(uint o, vec3 w, out vec3 normal) {
    vec4 qo = posedOrientation(o);
    float s = bodies[o].scale;
    vec3 local = rotate(vec4(-qo.xyz, qo.w), w - posedPosition(o)) / s + bodies[o].centerLocal;
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

// What one lane's contacts of a body found in a sweep: the sums of their position and rotation
// steps, their count, the deepest, how many touched (counted in the first sweep only) and the
// sum of their normals.
struct ContactSums {
    vec3 step;
    vec3 turn;
    uint count;
    float deepest;
    uint touching;
    vec3 normals;
};

ContactSums noContacts() {
    return ContactSums(vec3(0.0), vec3(0.0), 0u, 0.0, 0u, vec3(0.0));
}

// Adds one contact of body b, at arm `arm` from the centre (x, q), `depth` inside something whose
// unit normal there is n, of which the body takes `share` of the correction.
void addContact(inout ContactSums sums, uint b, vec3 x, vec4 q, vec3 arm, vec3 pStart, vec3 n,
                float depth, float share, bool first) {
    if (first) {
        sums.deepest = max(sums.deepest, depth);
        ++sums.touching;
    }
    sums.normals += n;
    vec3 dx, turn;
    correction(b, x, q, arm, pStart, n, depth, share, dx, turn);
    sums.step += dx;
    sums.turn += turn;
    ++sums.count;
}

// Lane `lane` of `lanes`'s share of body b's corrections against the other bodies in one
// sweep: its points lane, lane + lanes, ... tested against the bodies whose bounding spheres
// meet this one's, at their poses of this sweep's start. The corrections are summed, not
// applied: the sweep averages them over all the body's contacts.
ContactSums pairShare(uint b, uint lane, uint lanes, vec3 x0, vec4 q0, vec3 x, vec4 q,
                      bool first) {
    ContactSums sums = noContacts();
    GpuBody body = bodies[b];
    float reach = body.boundRadius;
    uint bodyMask = 0u, bodyMaskHigh = 0u; // bit o: body o's sphere meets this one's
    for (uint o = 0u; o < P.bodyCount; ++o) {
        vec3 d = posedPosition(o) - x;
        float r = reach + bodies[o].boundRadius;
        if (o != b && dot(d, d) < r * r) {
            if (o < 32u)
                bodyMask |= 1u << o;
            else
                bodyMaskHigh |= 1u << (o - 32u);
        }
    }
    if (bodyMask == 0u && bodyMaskHigh == 0u)
        return sums;
    mat3 invI = worldInvInertia(b, q);
    for (uint s = lane; s < body.sampleCount; s += lanes) {
        vec3 arm = armOf(b, s);
        vec3 pStart = x0 + rotate(q0, arm);
        vec3 w = x + rotate(q, arm);
        // Only the bodies in the mask, in ascending order (the sums' order is fixed).
        uvec2 nearBodies = uvec2(bodyMask, bodyMaskHigh);
        for (uint word = 0u; word < 2u; ++word) {
            uint bits = nearBodies[word];
            while (bits != 0u) {
                uint o = 32u * word + uint(findLSB(bits));
                bits &= bits - 1u;
                vec3 toOther = w - posedPosition(o);
                if (dot(toOther, toOther) >= bodies[o].boundRadius * bodies[o].boundRadius)
                    continue;
                vec3 n;
                float phi = bodyDistance(o, w, n);
                float len = length(n);
                if (!(phi < 0.0) || !(len > 0.0))
                    continue;
                n /= len;
                // The pair splits the correction by their inverse masses at the point; the
                // other body moves its share when it tests its own points against this one.
                float mine = inverseMassAt(b, invI, w - x, n);
                float theirs =
                    inverseMassAt(o, worldInvInertia(o, posedOrientation(o)), toOther, n);
                // Against another body the corrections of the sweep are averaged, not
                // chained: each point would otherwise see the depth the previous one left and
                // take its share of that again, and both bodies together would move the whole
                // depth each.
                addContact(sums, b, x, q, arm, pStart, n, -phi, mine / (mine + theirs), first);
            }
        }
    }
    return sums;
}

// What body b's bounding sphere, centred at `xStart` and grown by `grow` [m], may touch: the
// domain's walls below and above on each axis, and the static colliders (bit c; beyond 32
// always).
struct Reach {
    bvec3 wallLo;
    bvec3 wallHi;
    uint staticMask;
};

Reach reachOf(uint b, vec3 xStart, float grow) {
    Reach r;
    float reach = bodies[b].boundRadius + grow;
    r.wallLo = bvec3(false);
    r.wallHi = bvec3(false);
    if (P.hasDomain != 0u) {
        r.wallLo = lessThan(xStart - reach, P.domainMin - PBF_RADIUS);
        r.wallHi = greaterThan(xStart + reach, P.domainMax + PBF_RADIUS);
    }
    r.staticMask = 0u;
    uint statics = P.staticColliders, c = 0u;
    while (statics != 0u && nextStaticCollider(statics, c))
        if (mayTouch(c, xStart, reach))
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

// Lane `lane` of `lanes`'s share of body b's corrections against the domain's walls and the
// static colliders its sphere may reach (r), all at the same pose (x, q): summed, not applied,
// like the pairs' (Jacobi; the sweep averages them over the contacts).
ContactSums wallAndStaticShare(uint b, Reach r, uint lane, uint lanes, vec3 x0, vec4 q0, vec3 x,
                               vec4 q, bool first) {
    ContactSums sums = noContacts();
    if (!reachesAnything(r))
        return sums;
    for (uint s = lane; s < bodies[b].sampleCount; s += lanes) {
        vec3 arm = armOf(b, s);
        vec3 pStart = x0 + rotate(q0, arm);
        vec3 w = x + rotate(q, arm);
        for (int a = 0; a < 3; ++a) {
            if (!r.wallLo[a] && !r.wallHi[a])
                continue;
            vec2 beyond = wallDepths(a, w);
            if (!(beyond.x > 0.0) && !(beyond.y > 0.0))
                continue;
            vec3 n = vec3(0.0);
            n[a] = beyond.x > 0.0 ? 1.0 : -1.0;
            addContact(sums, b, x, q, arm, pStart, n, max(beyond.x, beyond.y), 1.0, first);
        }
        uint mask = r.staticMask, c = 0u;
        while (nextStaticCollider(mask, c)) {
            vec3 n;
            float phi = colliderDistance(c, w, n);
            float len = length(n);
            if (!(phi < 0.0) || !(len > 0.0))
                continue;
            addContact(sums, b, x, q, arm, pStart, n / len, -phi, 1.0, first);
        }
    }
    return sums;
}

// What lane `lane` of `lanes` finds of body b's sealed contacts at its pose of the substep start
// (x0, q0), over its points lane, lane + lanes, ... (the film model, docs/bodies.md, "The film
// under a body"): over the points within the rim band of a wall or a static collider whose
// outward normal n faces it (more than 120 degrees from the solid's normal m), each by its head
// of water under `level` [m along up], a = area * (level - height): `sealed` the sum of
// w a (n . m) m (w fading from 1 to 0 over the sealed band's last spacing), `turn` the sum of the
// moments (p - c) x w a n, `head` the sum of a (n . -m).
struct SealedSums {
    vec3 sealed;
    vec3 turn;
    float head;
};

SealedSums sealedShare(uint b, uint lane, uint lanes, vec3 x0, vec4 q0, float level) {
    SealedSums sums = SealedSums(vec3(0.0), vec3(0.0), 0.0);
    float areaScale = bodies[b].scale * bodies[b].scale;
    for (uint s = lane; s < bodies[b].sampleCount; s += lanes) {
        vec4 point = samples[bodies[b].sampleOffset + s];
        vec3 arm = rotate(q0, armOf(b, s));
        vec3 solidNormal;
        float gap = nearestSolidWithin(x0 + arm, rimBand(), solidNormal);
        if (!(gap < rimBand()))
            continue;
        float phi;
        vec3 grad;
        sampleCollider(bodies[b].collider, point.xyz, phi, grad);
        float len = length(grad);
        if (!(len > 0.0))
            continue;
        vec3 normal = rotate(q0, grad / len);
        float facing = dot(normal, solidNormal);
        if (!(facing < -0.5))
            continue;
        // The sealed ones push across the solid, their moments along their own normals (a push
        // across the solid at a tilted face's points would tip the body further).
        float head = point.w * areaScale * max(0.0, level - dot(x0 + arm, upOf()));
        float w = clamp((sealedBand() - gap) / (2.0 * PBF_RADIUS), 0.0, 1.0);
        sums.head += -facing * head;
        sums.sealed += w * head * facing * solidNormal;
        sums.turn += cross(arm, w * head * normal);
    }
    return sums;
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
    colliderRecords[c].worldToGrid = toGrid;
    colliderRecords[c].boundCentre = body.position;
    colliderRecords[c].motion = before * toGrid;
    colliderRecords[c].scale = s;
}

#endif // !__cplusplus

#endif // SLUICE_SHARED_BODY_CONTACTS_GLSL_H
