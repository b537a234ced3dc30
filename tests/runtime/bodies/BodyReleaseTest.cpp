// Cubes released in deep water or resting on the tank's floor (issue 25, docs/bodies.md): as
// dense as the water they stay where they are put, light ones come up and float, heavy ones
// stay down. Each case plays 3 s of a 4k-particle tank on llvmpipe.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "bodies/BodyTank.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;
using namespace bodytest;

class BodyReleases : public GpuTest {};

constexpr float kDeep = 16 * kSpacing; // the water's depth in releaseCube's tank

// A cube `ratio` times the water's density released at rest with its centre at `y` over water
// 16 spacings (two cube sizes) deep, in a tank 4 spacings wider than the cube on every side,
// `seconds` played deterministic: how far its centre strayed from its start at most [m], the
// lowest it went, its mean submerged share over the last second, and its state at the end.
struct Released {
    double farthest = 0.0;
    double lowest = 0.0;
    double lastSecondShare = 0.0;
    double draft = 0.0; ///< share of the cube under the water's level, mean over the last second
    BodyState body;
    Health health;
    bool bodyFinite = true;
};

// `tank` and `depth` default to that tank; the water's level is measured over the whole floor.
Released releaseCube(float ratio, float y, float seconds, float tank = kSide + 8 * kSpacing,
                     float depth = kDeep) {
    format::Scene scene = tankScene(glm::vec2(tank), depth, 1.0f);
    scene.colliders.push_back(cubeBody(glm::vec3(0.5f * tank, y, 0.5f * tank), ratio));
    SimulationOptions options;
    options.deterministic = true;
    auto sim = Simulation::create(scene, {cubeAsset(kSide)}, options);
    EXPECT_TRUE(sim) << sim.error().message();
    if (!sim)
        return {};
    Released out;
    const double start = sim->bodies().at(0).position.y;
    out.lowest = start;
    const int steps = int(std::lround(60 * seconds));
    for (int step = 0; step < steps; ++step) {
        sim->step();
        out.health.add(sim->readStats());
        out.body = sim->bodies().at(0);
        out.bodyFinite = out.bodyFinite && finite(out.body);
        out.farthest = std::max(out.farthest, std::abs(double(out.body.position.y) - start));
        out.lowest = std::min(out.lowest, double(out.body.position.y));
        if (step >= steps - 60) {
            out.lastSecondShare += out.body.submergedShare / 60.0;
            // The geometric draft against the level the water's volume gives, every frame. (The
            // columns between the cube and the walls, 4 spacings wide, are too few to take a level
            // from, as playCube does in its wider tank: docs/bodies.md.)
            const double level = volumeLevel(sim->particleCount(), sim->constants().volume,
                                             double(tank) * tank, out.body, kSide);
            out.draft += submergedShare(out.body, kSide, level) / 60.0;
        }
    }
    return out;
}

void expectHealthy(const Released& r, const char* what) {
    EXPECT_EQ(r.health.nonFinite, 0u) << what;
    EXPECT_EQ(r.health.inside, 0u) << what;
    EXPECT_TRUE(r.bodyFinite) << what;
}

// Issue 25: at 1.0 a cube neither rises nor sinks more than one particle spacing in 3 s,
// anywhere in the water column: with one water layer under it, in the middle, and with one layer
// over it. Every wall adds its boundary volume, so the water keeps its height and its pressure
// at the floor (docs/pbf.md, "Boundary volume").
void expectNeutralStays(const char* where, float y) {
    const Released r = releaseCube(1.0f, y, 3.0f);
    std::printf("neutral cube released %s (centre %.3f m): ends at %.4f m, at most %.2f "
                "spacings from its start in 3 s\n",
                where, y, r.body.position.y, r.farthest / kSpacing);
    EXPECT_LT(r.farthest, kSpacing) << where;
    expectHealthy(r, where);
}

TEST_F(BodyReleases, ABodyAsDenseAsTheWaterStaysWhereItIsReleasedOneLayerOverTheFloor) {
    expectNeutralStays("low", kSpacing + 0.5f * kSide);
}

TEST_F(BodyReleases, ABodyAsDenseAsTheWaterStaysWhereItIsReleasedInTheMiddle) {
    expectNeutralStays("middle", 0.5f * kDeep);
}

TEST_F(BodyReleases, ABodyAsDenseAsTheWaterStaysWhereItIsReleasedOneLayerUnderTheSurface) {
    expectNeutralStays("high", kDeep - kSpacing - 0.5f * kSide);
}

TEST_F(BodyReleases, ALightBodyDroppedIntoDeepWaterComesBackUpAndFloats) {
    // Issue 25: 0.5 dropped from 0.3 m above the water into water two cube sizes deep plunges,
    // comes back up and floats at its draft, touching nothing (a rock at half the water's
    // density dropped into shallow water used to stay on the floor).
    const float start = kDeep + 0.3f + 0.5f * kSide;
    const Released r = releaseCube(0.5f, start, 3.0f);
    std::printf("cube at 0.5 dropped from 0.3 m: lowest centre %.4f m, ends at %.4f m, submerged "
                "share %.3f over the last second, %u contacts\n",
                r.lowest, r.body.position.y, r.lastSecondShare, r.body.contacts);
    EXPECT_LT(r.lowest, r.body.position.y - kSpacing) << "it plunged deeper than it floats";
    // Floating: the water rose by the displaced volume over the tank's floor, about 0.01 m; a
    // floating cube at 0.5 has its centre there.
    EXPECT_GT(r.body.position.y, kDeep - 0.25 * kSide) << "it came back up";
    EXPECT_NEAR(r.lastSecondShare, 0.5, 0.1);
    EXPECT_EQ(r.body.contacts, 0u);
    expectHealthy(r, "dropped");
}

// Issue 25: cubes resting flat on the floor of the filled tank from the start, no water under
// them (a crate placed before the room floods). The film model gives the faces over the floor
// the pressure of the water over them (docs/bodies.md, "The film under a body").
Released restOnTheFloor(float ratio) {
    const float resting = 0.5f * kSide;
    const Released r = releaseCube(ratio, resting, 3.0f);
    std::printf("cube at %.1f resting on the floor: ends at %.4f m (at most %.4f m from its "
                "start), lowest face %.4f m, share %.3f by force and %.3f by draft over the "
                "last second, %u contacts\n",
                ratio, r.body.position.y, r.farthest, lowestPoint(r.body, kSide), r.lastSecondShare,
                r.draft, r.body.contacts);
    expectHealthy(r, "resting on the floor");
    return r;
}

// Issue 25: light cubes resting on the floor rise and float at their Archimedes draft within
// 0.05, touching nothing: the floor's boundary volume lets the water layers that get under a
// cube carry the pressure there, and the film model holds them to it (docs/bodies.md, "The film
// under a body").
void expectRisesToItsDraft(float ratio) {
    const Released r = restOnTheFloor(ratio);
    EXPECT_GT(r.body.position.y, 0.5f * kSide + 4 * kSpacing) << "it must rise";
    EXPECT_NEAR(r.draft, ratio, 0.05) << "it floats at its draft";
    EXPECT_EQ(r.body.contacts, 0u);
}

TEST_F(BodyReleases, ABodyAtThreeTenthsRestingOnTheFloorRisesToItsDraft) {
    expectRisesToItsDraft(0.3f);
}

TEST_F(BodyReleases, ABodyAtHalfRestingOnTheFloorRisesToItsDraft) {
    expectRisesToItsDraft(0.5f);
}

TEST_F(BodyReleases, ABodyAtSevenTenthsRestingOnTheFloorRisesToItsDraft) {
    expectRisesToItsDraft(0.7f);
}

// Issue 25: SimulationBodies.ABodyATenthLighterThanWaterFloatsAndOneATenthHeavier
// Sinks's releases (a 0.4 m tank 0.2 m deep, each cube's top level with the surface, its lowest
// face two water layers over the floor). With the walls' volume the water stands at its volume's
// height there, so 0.9 has to rise and 1.1 to sink through the layers under them, as the film
// model lets them (docs/bodies.md, "The film under a body").
TEST_F(BodyReleases, ATenthLighterRisesOffTheLayersUnderItAndATenthHeavierSinks) {
    const float tank = 0.4f, depth = 0.2f;
    const float start = depth - 0.5f * kSide;
    const Released light = releaseCube(0.9f, start, 2.5f, tank, depth);
    const Released heavy = releaseCube(1.1f, start, 4.0f, tank, depth);
    std::printf("released at the surface: 0.9 ends at %.4f m (draft %.3f), 1.1 at "
                "%.4f m (lowest face %.4f m)\n",
                light.body.position.y, light.draft, heavy.body.position.y,
                lowestPoint(heavy.body, kSide));
    EXPECT_GT(light.body.position.y, start + 0.5f * kSpacing) << "0.9 must rise";
    EXPECT_LT(light.draft, 0.95) << "and keep part of itself out of the water";
    EXPECT_GT(light.draft, 0.75);
    EXPECT_EQ(light.body.contacts, 0u) << "it floats, touching nothing";
    EXPECT_LT(heavy.body.position.y, start - 0.02f) << "1.1 must sink";
    EXPECT_GT(lowestPoint(heavy.body, kSide), -0.5 * kSpacing) << "without sinking into the floor";
    expectHealthy(light, "0.9 released at the surface");
    expectHealthy(heavy, "1.1 released at the surface");
}

TEST_F(BodyReleases, AHeavyBodyRestingOnTheFloorStaysDown) {
    // 1.2 stays down, on at most one trapped water layer (as the heavy-body test allows).
    const Released r = restOnTheFloor(1.2f);
    EXPECT_LT(lowestPoint(r.body, kSide), kSpacing) << "it stays down";
    EXPECT_LT(r.farthest, kSpacing) << "it never rose a water layer";
}

} // namespace
} // namespace sluice::rt
