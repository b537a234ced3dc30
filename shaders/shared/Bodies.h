// Dynamic bodies shared by C++ and GLSL: the body record, the fixed-point reaction sums the
// solver passes add into, and their bindings (docs/bodies.md is the algorithm).
#ifndef SLUICE_SHARED_BODIES_H
#define SLUICE_SHARED_BODIES_H

#include "shared/GlslBridge.h"

SLUICE_SHARED_BEGIN

/// Bodies one body pass holds at most (a scene has at most 64 colliders, each may be a body).
SLUICE_CONST uint kMaxBodies = 64;
/// Invocations of a body's work group in the body pass (pbf_bodies.comp, one work group per
/// body), which split its contact points: kBodyLanes on a GPU, kBodyLanesSoftware on a software
/// renderer, which runs a group's invocations a SIMD vector at a time on one CPU thread (one
/// vector of 8; the groups spread over the threads). SimulationOptions::bodyGroupSize may pick
/// any power of two from kBodyLanesMin to kBodyLanesMax.
SLUICE_CONST uint kBodyLanes = 128;
SLUICE_CONST uint kBodyLanesSoftware = 8;
SLUICE_CONST uint kBodyLanesMin = 8;
SLUICE_CONST uint kBodyLanesMax = 512;
/// Jacobi sweeps of the contacts a substep, one dispatch each (with more than one body): the
/// bodies exchange their poses through kBindBodySteps between sweeps.
SLUICE_CONST uint kBodyContactSweeps = 4;
/// GpuCollider::body of a collider that is not a dynamic body.
SLUICE_CONST uint kNoBody = 0xffffffffu;
/// Fixed-point words per body in the reaction sums (kBindBodySums): four vector sums of three
/// components, each component two unsigned 64-bit integers (low word, high word), the sum of
/// its positive terms' magnitudes and that of its negative terms', so integer adds from any
/// number of particles in any order give the same total, and an add carries into a high word
/// only when the low word wraps (a two's-complement sum would carry every negative term's sign
/// into it: twice the atomics, which were most of the reactions' cost, docs/bodies.md):
///
///   word  0      12       24          36            48      60             72        73    80
///         | push | moment | held push | held moment | under | under moment | surface | spare |
///
/// `push` is the sum of the corrections dx the body gave particles [GpuBody::sumScale units of
/// m], `moment` the sum of (x - c) x dx [momentScale units of m^2]; the held pair the same for
/// the collision pushes a wall undid (the body takes only what stops it moving into the
/// particles the wall holds, docs/bodies.md). Read and write them through bodySumWord.
/// `under` is the sum of the pushes across a wall or a static collider the body gave the water
/// within the rim band of it, the water between the body and the solid [sumScale units of m],
/// and `under moment` their moments [momentScale units of m^2]; the film model (docs/bodies.md,
/// "The film under a body") holds them to the pressure of the water over the body, whose level
/// is the one plain word `surface`: the highest compressed water in the column over the body
/// (FilmGlsl.h, surfaceWordOf), maxed with an integer atomic.
SLUICE_CONST uint kBodySumWords = 80;
SLUICE_CONST uint kBodySumPush = 0;
SLUICE_CONST uint kBodySumMoment = 12;
SLUICE_CONST uint kBodySumHeldPush = 24;
SLUICE_CONST uint kBodySumHeldMoment = 36;
SLUICE_CONST uint kBodySumUnder = 48;
SLUICE_CONST uint kBodySumUnderMoment = 60;
SLUICE_CONST uint kBodySumSurface = 72;
/// Words of a body's sums in use; the rest up to kBodySumWords are spare.
SLUICE_CONST uint kBodySumUsed = 73;
/// Contact sample points of one body at most.
SLUICE_CONST uint kMaxBodySamples = 2048;

// The body coupling's tuned constants: the one table of them, with the measurement that set
// each and the test that holds it, is docs/bodies.md, "Tuned constants" (with the surface
// offset, format::kBodySurfaceOffsetSpacings, which the baker needs too).
/// The share of the film model's contact points' area taken as the faces' (their areas sum to
/// about 1.19 times a cube's faces at 8 points a side: the cells along its edges hold points of
/// the rounded field).
SLUICE_CONST float kFilmAreaShare = 0.84;
/// How fast the film under a body drains [m/s]: the film model gives back what it took off the
/// water under the body only as far as it holds the body's approach to the solid to this.
SLUICE_CONST float kFilmDrainSpeed = 0.05;
/// The sealed band, where a body's face over a wall or a static collider is held by the film
/// model: within h + this many particle radii of the solid (at most three water layers).
SLUICE_CONST float kSealedBandRadii = 2.5;
/// The viewer's mouse spring on a body: its natural frequency [Hz], critically damped.
SLUICE_CONST float kDragSpringHz = 3.0;

/// Fixed-point units of the push sums per kernel radius h: a body's sumScale and a measured
/// collider's are this / h [1/m] (2^28: a push of h is 2^28, far below the 2^31 one add holds).
SLUICE_CONST float kSumUnitsPerH = 268435456.0;

/// The low word of component `axis` (0 x, 1 y, 2 z) of body `body`'s sum that starts at word
/// `sum` (kBodySumPush, ...): the positive part's low and high words, then the negative part's
/// (kBodySumNegative words on).
SLUICE_FUNC uint bodySumWord(uint body, uint sum, uint axis) {
    return body * kBodySumWords + sum + 4u * axis;
}
SLUICE_CONST uint kBodySumNegative = 2;

SLUICE_CONST uint kBindBodies = 22;        ///< GpuBody[]
SLUICE_CONST uint kBindBodySums = 23;      ///< uint[kBodySumWords] per body
SLUICE_CONST uint kBindBodySamples = 24;   ///< vec4 contact points, body-local [asset units]
SLUICE_CONST uint kBindBodySteps = 25;     ///< GpuBodyStep[]: the body pass's state between sweeps
SLUICE_CONST uint kBindColliderForces = 28; ///< GpuColliderForce[kMaxColliders]
SLUICE_CONST uint kBindCollidersNear = 26; ///< uvec4 per sorted particle: the colliders that may
                                           ///< reach it in its substep and in the iteration
                                           ///< (CollidersNearGlsl.h)

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
    /* 204 */ uint kinematic;       ///< 1 while the game moves it (Simulation::setBodyKinematic):
                                    ///< its velocities are the game's, invMass and invInertia 0
};

/// The fluid's force on a collider that is no body, when measured (Simulation::measureForce):
/// the mean over the step's substeps, the torque about its origin. Written by
/// pbf_collider_forces.comp from the sums in the collider's slot (GpuCollider::forceSlot).
struct GpuColliderForce {
    /*   0 */ vec3 force;  ///< [N]
    /*  12 */ float pad0;
    /*  16 */ vec3 torque; ///< [N m]
    /*  28 */ float pad1;
};

/// A body's pose in the body pass: centre of mass [m] and orientation.
struct GpuBodyPose {
    /*   0 */ vec3 position;
    /*  12 */ float pad0;
    /*  16 */ vec4 orientation;
};

/// A body between the dispatches of one body pass (pbf_bodies.comp): written by the start, read
/// and advanced by each contact sweep. Sweep k reads poses[k % 2] (every body's pose at the
/// sweep's start) and writes its own body's poses[(k + 1) % 2], so no body reads a pose another
/// is writing.
struct GpuBodyStep {
    /*   0 */ GpuBodyPose poses[2];
    /*  64 */ vec3 startPosition;   ///< pose at the substep start
    /*  76 */ float deepest;        ///< deepest contact of the first sweep [m]
    /*  80 */ vec4 startOrientation;
    /*  96 */ vec3 velocity;        ///< after reaction and gravity, before contacts [m/s]
    /* 108 */ uint touching;        ///< contacts of the first sweep
    /* 112 */ vec3 force;           ///< the fluid's force this substep [N]
    /* 124 */ float pad1;
    /* 128 */ vec3 torque;          ///< the fluid's torque this substep [N m]
    /* 140 */ float pad2;
    /* 144 */ vec3 normalSum;       ///< sum of the contacts' normals over the sweeps
    /* 156 */ float pad3;
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
SLUICE_BODY_AT(kinematic, 204);
static_assert(sizeof(sluice::shared::GpuBody) == 208, "std430 size of GpuBody");
static_assert(sluice::shared::kBodySumMoment == sluice::shared::kBodySumPush + 12 &&
                  sluice::shared::kBodySumHeldPush == sluice::shared::kBodySumMoment + 12 &&
                  sluice::shared::kBodySumHeldMoment == sluice::shared::kBodySumHeldPush + 12 &&
                  sluice::shared::kBodySumUnder == sluice::shared::kBodySumHeldMoment + 12 &&
                  sluice::shared::kBodySumUnderMoment == sluice::shared::kBodySumUnder + 12 &&
                  sluice::shared::kBodySumSurface == sluice::shared::kBodySumUnderMoment + 12 &&
                  sluice::shared::kBodySumUsed == sluice::shared::kBodySumSurface + 1 &&
                  sluice::shared::kBodySumUsed <= sluice::shared::kBodySumWords,
              "the body sums' layout");
static_assert(sizeof(sluice::shared::GpuColliderForce) == 32, "std430 size of GpuColliderForce");
static_assert(sizeof(sluice::shared::GpuBodyPose) == 32, "std430 size of GpuBodyPose");
static_assert(offsetof(sluice::shared::GpuBodyStep, startPosition) == 64 &&
                  offsetof(sluice::shared::GpuBodyStep, velocity) == 96 &&
                  offsetof(sluice::shared::GpuBodyStep, force) == 112 &&
                  offsetof(sluice::shared::GpuBodyStep, normalSum) == 144 &&
                  sizeof(sluice::shared::GpuBodyStep) == 160,
              "std430 layout of GpuBodyStep");
static_assert((sluice::shared::kBodyLanes & (sluice::shared::kBodyLanes - 1)) == 0 &&
                  (sluice::shared::kBodyLanesSoftware & (sluice::shared::kBodyLanesSoftware - 1)) ==
                      0,
              "a body's lanes are summed in a tree: a power of two");
#undef SLUICE_BODY_AT
#endif

#endif // SLUICE_SHARED_BODIES_H
