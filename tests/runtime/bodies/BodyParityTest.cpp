// Dynamic bodies in the GPU solver against the CPU reference (tests/reference): the fluid's
// force and torque on a body after one substep, and the particles, by id.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "GpuTest.h"
#include "ReferencePbf.h"
#include "RuntimeTestScenes.h"
#include "bodies/BodySetup.h"
#include "sim/ParticleCompare.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using test::maxPositionDifference;

using gpu::test::GpuTest;

constexpr float kSpacing = 0.02f;

// A 16 x 8 x 16 block (2048 particles, 0.16 m deep) in a 0.32 m tank, one substep a step and a
// fixed 8 iterations (targetDensityError = 0, so no early stop can split the two sides), on a
// static floor slab rotated 30 degrees about y (friction 0.3), with dynamic boxes after it in
// scene order.
struct BodyScene {
    format::Scene scene;
    std::vector<format::ColliderAsset> assets;
};

BodyScene tankWithFloor() {
    BodyScene b;
    b.scene = testscene::smallScene({16, 8, 16}, kSpacing, 1);
    b.scene.simulation.targetDensityError = 0.0f;
    // Its top is the tank's floor, y = 0.
    testscene::addTiltedFloor(b.scene, b.assets);
    return b;
}

// Adds a dynamic box [lo, hi] (asset units; the asset origin is off its centre, so the centre
// of mass is too) at half the water's density, placed by `translation`, Euler `degrees` and
// `scale`, with `friction` against the particles.
void addBox(BodyScene& b, glm::dvec3 lo, glm::dvec3 hi, glm::vec3 translation, glm::vec3 degrees,
            float scale, float friction) {
    b.assets.push_back(testscene::boxColliderAsset(lo, hi, 0.25 * kSpacing));
    format::SceneCollider box;
    box.asset = "box.slc";
    box.translation = translation;
    box.rotationDegrees = degrees;
    box.scale = scale;
    box.friction = friction;
    format::DynamicBody body;
    body.density = 500.0f;
    box.dynamic = body;
    b.scene.colliders.push_back(box);
}

// The reference's colliders: the scene's, each body held at the pose and centre of mass the GPU
// starts it at, with the GPU's contact points.
std::vector<ref::ReferenceCollider> referenceColliders(const BodyScene& b,
                                                       const std::vector<BodyState>& bodies) {
    const PbfConstants k = deriveConstants(b.scene.simulation);
    auto setup = setUpBodies(b.scene, b.assets, k);
    EXPECT_TRUE(setup) << setup.error().message();
    std::vector<ref::ReferenceCollider> out;
    for (std::size_t c = 0; c < b.assets.size(); ++c)
        out.push_back({&b.assets[c], b.scene.colliders[c]});
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const BodyState& body = bodies[i];
        ref::ReferenceCollider& c = out[body.collider];
        c.centerOfMass = body.position;
        c.bodyPose = body.pose;
        c.mass = body.mass;
        c.linearVelocity = body.linearVelocity;
        c.angularVelocity = body.angularVelocity;
        if (setup && i < setup->records.size()) {
            // As pbf_bodies.comp's worldInvInertia: R I^-1 R^T, R the body's orientation.
            const glm::mat3 r = glm::mat3_cast(body.orientation);
            c.invInertia = r * glm::mat3(setup->records[i].invInertia) * glm::transpose(r);
        }
        c.contactPoints =
            bodyContactPoints(b.assets[body.collider], b.scene.colliders[body.collider].scale, k);
    }
    return out;
}

struct Parity {
    double position = 0.0; ///< largest particle position difference [m]
    double force = 0.0;    ///< worst body's |F_gpu - F_cpu| / |F_cpu|
    double torque = 0.0;   ///< worst body's |T_gpu - T_cpu| / |T_cpu|
    double held = 0.0;     ///< largest |held force| of a body on the reference [N]
    glm::dvec3 forceGpu{0.0}, forceCpu{0.0};   ///< the last body's [N]
    glm::dvec3 torqueGpu{0.0}, torqueCpu{0.0}; ///< [N m]
    glm::dvec3 sealed{0.0}; ///< the last body's sealed force on the reference [N]
};

// One step (one substep) of the scene on the GPU and one substep of the reference; the GPU
// neighbour search must use the dense grid or the hash as `denseGrid` says. `turned`: each
// body's torque must be worth comparing relative to itself (see below).
Parity runOneSubstep(const BodyScene& b, bool denseGrid, std::uint32_t lanes = 1,
                     bool turned = true) {
    Parity out;
    SimulationOptions options;
    options.deterministic = true;
    options.neighbourLanes = lanes;
    auto gpu = Simulation::create(b.scene, b.assets, options);
    EXPECT_TRUE(gpu) << gpu.error().message();
    if (!gpu)
        return out;
    EXPECT_EQ(gpu->neighbourGridCells().x > 0, denseGrid);
    const std::vector<BodyState> start = gpu->bodies();
    ref::ReferencePbf cpu(b.scene, referenceColliders(b, start));
    EXPECT_EQ(cpu.bodyCount(), start.size());
    EXPECT_GT(gpu->particlesRemovedAtSpawn(), 0u) << "each body starts in the water";
    EXPECT_EQ(gpu->particlesRemovedAtSpawn(), cpu.particlesRemovedAtSpawn());
    EXPECT_EQ(maxPositionDifference(gpu->downloadParticles(), cpu.particles()), 0.0)
        << "both start from the same particles";

    gpu->step();
    cpu.substep();
    out.position = maxPositionDifference(gpu->downloadParticles(), cpu.particles());
    const std::vector<BodyState> after = gpu->bodies();
    EXPECT_EQ(after.size(), cpu.bodyCount());
    for (std::size_t i = 0; i < std::min(after.size(), cpu.bodyCount()); ++i) {
        const glm::dvec3 fGpu(after[i].force), tGpu(after[i].torque);
        const glm::dvec3 fCpu = cpu.bodyForce(i), tCpu = cpu.bodyTorque(i);
        out.force = std::max(out.force, glm::length(fGpu - fCpu) / glm::length(fCpu));
        out.torque = std::max(out.torque, glm::length(tGpu - tCpu) / glm::length(tCpu));
        out.held = std::max(out.held, glm::length(cpu.bodyHeldForce(i)));
        out.forceGpu = fGpu;
        out.forceCpu = fCpu;
        out.torqueGpu = tGpu;
        out.torqueCpu = tCpu;
        out.sealed = cpu.bodySealedForce(i);
        std::printf("body %zu: force GPU (%.6f, %.6f, %.6f) CPU (%.6f, %.6f, %.6f) N, torque GPU "
                    "(%.7f, %.7f, %.7f) CPU (%.7f, %.7f, %.7f) N m\n",
                    i, fGpu.x, fGpu.y, fGpu.z, fCpu.x, fCpu.y, fCpu.z, tGpu.x, tGpu.y, tGpu.z,
                    tCpu.x, tCpu.y, tCpu.z);
        // The comparison means something only if the body is pushed and turned: a force of
        // 0.1 N or more, and a torque of at least |F| times a 1 mm lever (each is then compared
        // relative to its own magnitude).
        EXPECT_GT(glm::length(fCpu), 0.1) << "body " << i;
        if (turned) {
            EXPECT_GT(glm::length(tCpu), 1e-3 * glm::length(fCpu)) << "body " << i;
        }
    }
    std::printf("parity after one substep: particles %.3g h, force %.3g, torque %.3g "
                "(relative)\n",
                out.position / b.scene.simulation.kernelRadius, out.force, out.torque);
    return out;
}

// GPU and reference agree after the substep: particles within 1e-4 h, the bodies' forces and
// torques within 1e-4 of their own magnitude.
void expectParity(const Parity& p, const BodyScene& b) {
    EXPECT_LT(p.position, 1e-4 * b.scene.simulation.kernelRadius);
    EXPECT_LT(p.force, 1e-4);
    EXPECT_LT(p.torque, 1e-4);
}

class BodyParity : public GpuTest {};

TEST_F(BodyParity, ForcesAndTorquesMatchTheCpuReferenceAfterOneSubstep) {
    BodyScene b = tankWithFloor();
    // A 0.08 x 0.06 x 0.07 m box, tilted on all three axes and about half under water, off the
    // tank's centre: the water pushes its submerged corner up, so the torque is well away
    // from 0.
    addBox(b, {-0.03, -0.025, -0.04}, {0.05, 0.035, 0.03}, glm::vec3(0.171f, 0.1553f, 0.143f),
           glm::vec3(15.0f, 25.0f, -10.0f), 1.0f, 0.2f);
    const Parity p = runOneSubstep(b, true);
    // Measured on llvmpipe: particles 1.9e-6 h, force 1.1e-5, torque 1.4e-5 relative.
    expectParity(p, b);
}

// The neighbour passes split over 4 invocations per particle (the layout a GPU picks for small
// scenes) add the same sums in another order: the bodies' boundary terms, only on lane 0, and
// the reactions come out as the reference's.
TEST_F(BodyParity, NeighbourLanesMatchTheCpuReferenceToo) {
    BodyScene b = tankWithFloor();
    addBox(b, {-0.03, -0.025, -0.04}, {0.05, 0.035, 0.03}, glm::vec3(0.171f, 0.1553f, 0.143f),
           glm::vec3(15.0f, 25.0f, -10.0f), 1.0f, 0.2f);
    const Parity p = runOneSubstep(b, true, 4);
    expectParity(p, b);
}

// The box of the test above scaled by 1.25 and without friction, over a flat box lying under
// water about two spacings below its lowest corner, so the particles between feel both
// boundaries.
void addBoxOverFlatBox(BodyScene& b) {
    addBox(b, {-0.03, -0.025, -0.04}, {0.05, 0.035, 0.03}, glm::vec3(0.171f, 0.1653f, 0.143f),
           glm::vec3(15.0f, 25.0f, -10.0f), 1.25f, 0.0f);
    addBox(b, {-0.04, -0.015, -0.03}, {0.04, 0.015, 0.03}, glm::vec3(0.183f, 0.0551f, 0.137f),
           glm::vec3(0.0f, 40.0f, 5.0f), 1.0f, 0.1f);
}

TEST_F(BodyParity, TwoScaledBodiesOnTheHashGridMatchTheCpuReference) {
    BodyScene b = tankWithFloor();
    // The domain reaching up to 100 m makes the solver hash its cells instead of the dense grid.
    b.scene.domainMax->y = 100.0f;
    addBoxOverFlatBox(b);
    const Parity p = runOneSubstep(b, false);
    // Measured on llvmpipe: particles 2.1e-6 h, force 8.8e-6, torque 6.6e-6 relative.
    expectParity(p, b);
}

// The solve's passes visit, after their first iteration, only the bodies the lambda pass found
// within reach of x*, and all of them again for a particle that moved farther than h / 16 in
// the iteration (docs/bodies.md, "Bodies near a particle"). Water thrown down at 0.5 m/s onto
// the floor and the two boxes of the test above (on the dense grid here) moves by millimetres an
// iteration, towards bodies whose field it may not have reached at the iteration's start; the
// reference visits every body every time. (At 1 m/s float and double part by 1.4e-4 h whatever
// the lists do.)
TEST_F(BodyParity, WaterThrownAtTwoBodiesMatchesTheCpuReference) {
    BodyScene b = tankWithFloor();
    b.scene.blocks.at(0).velocity = glm::vec3(0.0f, -0.5f, 0.0f);
    addBoxOverFlatBox(b);
    const Parity p = runOneSubstep(b, true);
    // Measured on llvmpipe: particles 2.2e-6 h, force 6.2e-6, torque 7.2e-6 relative; with the
    // lists' margins taken out (bodies kept only where phi < h, no fall-back to the substep's
    // mask) 1.1e-3 h, 2.8e-3 and 2.5e-3.
    expectParity(p, b);
}

// An 8 cm box under water, its -x face 0.1 spacing from the plane the domain's wall holds the
// particles' centres at, moving towards that wall at 0.2 m/s: the column of water between is
// pushed into the wall, which puts it back. What the wall undoes of the box's push-out is the
// held reaction, of which the box takes only what stops it (docs/bodies.md, "Particles held
// against a wall"), where it acts, with the body's spin after the rest of the reaction and its
// effective mass there (pbf_bodies.comp, takeHeldReaction); the film model holds the faces
// within its band of the wall and the floor at the water's head.
TEST_F(BodyParity, ABodyPressingWaterIntoAWallMatchesTheCpuReference) {
    BodyScene b = tankWithFloor();
    addBox(b, {-0.04, -0.04, -0.04}, {0.04, 0.04, 0.04}, glm::vec3(0.052f, 0.08f, 0.161f),
           glm::vec3(0.0f), 1.0f, 0.0f);
    b.scene.colliders.back().dynamic->linearVelocity = glm::vec3(-0.2f, 0.0f, 0.0f);
    // The torque is that of a lever under 1 mm here: compared below against the film's push.
    const Parity p = runOneSubstep(b, true, 1, false);
    std::printf("held force on the reference: %.4f N; sealed (%.4f, %.4f, %.4f) N\n", p.held,
                p.sealed.x, p.sealed.y, p.sealed.z);
    EXPECT_GT(p.held, 0.1) << "the wall must hold particles against the box";
    EXPECT_GT(glm::length(p.sealed), 1.0) << "the film model holds the faces by the wall";
    EXPECT_LT(p.position, 1e-4 * b.scene.simulation.kernelRadius);
    // Along the held impulse (+x) to 1e-4 of the held force: measured 7e-4 N of 18.4 N; taken
    // at the centre (not where it acts), 9e-3 N.
    EXPECT_LT(std::abs(p.forceGpu.x - p.forceCpu.x), 1e-4 * p.held);
    // The rest to a thousandth of the film's push, as the sealed box's below (and the torque to
    // that push times the box's half width): measured 8e-3 N of 20.8 N and 3e-4 N m. The film
    // reads the level and which solid each particle under the box is nearest to, and a particle
    // in the corner of the wall and the floor is about as near to each.
    EXPECT_LT(glm::length(p.forceGpu - p.forceCpu), 1e-3 * glm::length(p.sealed));
    EXPECT_LT(glm::length(p.torqueGpu - p.torqueCpu), 1e-3 * glm::length(p.sealed) * 0.04);
}

// One substep of a box sealed on the floor on the GPU and on the CPU reference: an 8 x 4 x 8 cm
// box in the middle of the tank, its bottom 4 mm above the floor under 12 cm of water, no
// particle fits under it, and the film model gives its bottom the pressure of the water over it
// (docs/bodies.md, "The film under a body"). Its grid (5 mm) is placed off the particles'
// lattice (2 cm): at 0.16 m every particle beside it sat on a plane of its grid, where the
// trilinear field's gradient jumps, and the GPU (float) and the reference (double) rounded to
// cells on either side: 1.1e-3 h apart after the substep, against 1.7e-6 h here.
TEST_F(BodyParity, ABodySealedOnTheFloorMatchesTheCpuReference) {
    BodyScene b = tankWithFloor();
    addBox(b, {-0.04, -0.02, -0.04}, {0.04, 0.02, 0.04}, glm::vec3(0.1613f, 0.024f, 0.1613f),
           glm::vec3(0.0f), 1.0f, 0.0f);
    SimulationOptions options;
    options.deterministic = true;
    auto gpu = Simulation::create(b.scene, b.assets, options);
    ASSERT_TRUE(gpu) << gpu.error().message();
    ref::ReferencePbf cpu(b.scene, referenceColliders(b, gpu->bodies()));
    gpu->step();
    cpu.substep();
    const glm::dvec3 sealed = cpu.bodySealedForce(0);
    const glm::dvec3 fGpu(gpu->bodies().at(0).force), fCpu = cpu.bodyForce(0);
    const double particles = maxPositionDifference(gpu->downloadParticles(), cpu.particles());
    std::printf("sealed force on the reference (%.5f, %.5f, %.5f) N; the fluid's force GPU "
                "(%.5f, %.5f, %.5f) CPU (%.5f, %.5f, %.5f) N; particles %.3g h apart\n",
                sealed.x, sealed.y, sealed.z, fGpu.x, fGpu.y, fGpu.z, fCpu.x, fCpu.y, fCpu.z,
                particles / b.scene.simulation.kernelRadius);
    EXPECT_GT(sealed.y, 1.0) << "the sealed bottom is pushed up";
    EXPECT_LT(std::abs(sealed.x) + std::abs(sealed.z), 1e-3 * sealed.y) << "across the floor";
    EXPECT_LT(particles, 1e-4 * b.scene.simulation.kernelRadius);
    // The fluid's force, sealed push included, to a thousandth of that push. A point on the
    // box's edge lies on its grid's planes, its normal is the one face's in one cell and the
    // other's in the next: the reference takes the contact points' normals in the GPU's cells.
    EXPECT_LT(glm::length(fGpu - fCpu), 1e-3 * glm::length(sealed));
}

} // namespace
} // namespace sluice::rt
