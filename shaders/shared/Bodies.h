// Dynamic bodies shared by C++ and GLSL: the body record, the fixed-point reaction sums the
// solver passes add into, and their bindings (docs/bodies.md is the algorithm).
#ifndef SLUICE_SHARED_BODIES_H
#define SLUICE_SHARED_BODIES_H

#include "shared/GlslBridge.h"

SLUICE_SHARED_BEGIN

/// Bodies one body pass holds at most: one work group holds every body (a scene has at most 64
/// colliders), so body-body contacts exchange poses through shared memory.
SLUICE_CONST uint kBodyLocalSize = 64;
/// Invocations of the body pass's work group on a GPU: each body gets the same power-of-two
/// share of them (8 with 64 bodies, all 512 with one), which split its contact points.
SLUICE_CONST uint kBodyGroupSize = 512;
/// GpuCollider::body of a collider that is not a dynamic body.
SLUICE_CONST uint kNoBody = 0xffffffffu;
/// Fixed-point words per body in the reaction sums: twice 6 components (sum of dx [m], sum of
/// r x dx [m^2]), each a 64-bit two's-complement integer split in a low and a high word: words
/// 0-11 the reaction the body takes, words 12-23 the collision pushes a wall undid (the body
/// takes only what stops it moving into the particles the wall holds), 24-31 spare.
SLUICE_CONST uint kBodySumWords = 32;
/// First word of the held-particle sums.
SLUICE_CONST uint kBodyHeldWords = 12;
/// Contact sample points of one body at most.
SLUICE_CONST uint kMaxBodySamples = 2048;

SLUICE_CONST uint kBindBodies = 22;     ///< GpuBody[]
SLUICE_CONST uint kBindBodySums = 23;   ///< uint[kBodySumWords] per body
SLUICE_CONST uint kBindBodySamples = 24; ///< vec4 contact points, body-local [asset units]

/// One dynamic body. The solver reads its pose through its GpuCollider record, which the body
/// pass rewrites after every substep. std430; offsets [bytes] on the left are checked below.
// clang-format off
struct GpuBody {
    /*   0 */ vec3 position;        ///< centre of mass, world [m]
    /*  12 */ float invMass;        ///< [1/kg]
    /*  16 */ vec4 orientation;     ///< unit quaternion (x, y, z, w): body-local -> world
    /*  32 */ vec3 linearVelocity;  ///< of the centre of mass [m/s]
    /*  44 */ float mass;           ///< [kg]
    /*  48 */ vec3 angularVelocity; ///< world [rad/s]
    /*  60 */ uint collider;        ///< index of its GpuCollider
    /*  64 */ mat4 invInertia;      ///< body-local inverse inertia about the centre of mass (3x3) [1/(kg m^2)]
    /* 128 */ vec3 centerLocal;     ///< centre of mass in the asset frame [asset units]
    /* 140 */ float scale;          ///< uniform placement scale: asset units -> m
    /* 144 */ vec3 force;           ///< the fluid's force on the body, mean over the last step [N]
    /* 156 */ float sumScale;       ///< fixed-point units per metre of the dx sums
    /* 160 */ vec3 torque;          ///< the fluid's torque about the centre of mass, mean [N m]
    /* 172 */ float momentScale;    ///< fixed-point units per m^2 of the r x dx sums
    /* 176 */ uint sampleOffset;    ///< first contact point in the samples buffer
    /* 180 */ uint sampleCount;     ///< contact points
    /* 184 */ float friction;       ///< Coulomb coefficient of its contacts
    /* 188 */ float restitution;    ///< share of the approach speed kept after an impact
    /* 192 */ float boundRadius;    ///< world radius of a sphere about the centre holding the solid [m]
    /* 196 */ float contactDepth;   ///< deepest penetration of its contacts, last substep [m]
    /* 200 */ uint contacts;        ///< contact points that touched something, last substep
    /* 204 */ uint pad0;
};
// clang-format on

SLUICE_SHARED_END

#ifdef __cplusplus
#include <cstddef>
#define SLUICE_BODY_AT(field, offset)                                                              \
    static_assert(offsetof(sluice::shared::GpuBody, field) == (offset), "std430 offset of " #field)
SLUICE_BODY_AT(invMass, 12);
SLUICE_BODY_AT(orientation, 16);
SLUICE_BODY_AT(linearVelocity, 32);
SLUICE_BODY_AT(mass, 44);
SLUICE_BODY_AT(angularVelocity, 48);
SLUICE_BODY_AT(collider, 60);
SLUICE_BODY_AT(invInertia, 64);
SLUICE_BODY_AT(centerLocal, 128);
SLUICE_BODY_AT(scale, 140);
SLUICE_BODY_AT(force, 144);
SLUICE_BODY_AT(sumScale, 156);
SLUICE_BODY_AT(torque, 160);
SLUICE_BODY_AT(momentScale, 172);
SLUICE_BODY_AT(sampleOffset, 176);
SLUICE_BODY_AT(friction, 184);
SLUICE_BODY_AT(boundRadius, 192);
SLUICE_BODY_AT(contacts, 200);
static_assert(sizeof(sluice::shared::GpuBody) == 208, "std430 size of GpuBody");
#undef SLUICE_BODY_AT
#endif

#endif // SLUICE_SHARED_BODIES_H
