// The panel's body rows without a window: the submerged share's average over simulated time,
// restarts on reset, and the plain figures.
#include <cmath>

#include <gtest/gtest.h>

#include "viewer/ViewerBodies.h"

namespace sluice::rt {
namespace {

format::Scene sceneWithBody(const std::string& asset) {
    format::Scene scene;
    scene.colliders.resize(2);
    scene.colliders[0].asset = "tank.slc";
    scene.colliders[1].asset = asset;
    scene.colliders[1].dynamic = format::DynamicBody{};
    return scene;
}

BodyState body(double share) {
    BodyState b;
    b.collider = 1;
    b.mass = 0.25;
    b.submergedShare = share;
    return b;
}

constexpr double kFrame = 1.0 / 60.0; // [s]

TEST(BodyReadout, AStepInTheShareIsTwoThirdsThroughAfterHalfASecond) {
    const format::Scene scene = sceneWithBody("box.slc");
    BodyReadout readout;
    readout.update(scene, {body(0.0)}, 0.0);
    double t = 0.0;
    for (int i = 0; i < 30; ++i) {
        t += kFrame;
        readout.update(scene, {body(1.0)}, t);
    }
    ASSERT_EQ(readout.rows().size(), 1u);
    // An exponential average with time constant 0.5 s: 1 - 1/e after 0.5 s.
    EXPECT_NEAR(readout.rows()[0].submerged, 1.0 - std::exp(-1.0), 1e-9);
    EXPECT_DOUBLE_EQ(BodyReadout::kSmoothingTime, 0.5);
}

TEST(BodyReadout, NoiseFromStepToStepIsAveragedOut) {
    const format::Scene scene = sceneWithBody("box.slc");
    BodyReadout readout;
    double t = 0.0;
    double worst = 0.0;
    for (int i = 0; i < 240; ++i) {
        readout.update(scene, {body(i % 2 == 0 ? 0.2 : 0.8)}, t);
        if (t > 1.5)
            worst = std::max(worst, std::abs(readout.rows()[0].submerged - 0.5));
        t += kFrame;
    }
    // Raw values 0.3 away from the mean; the average stays within 0.02 of it.
    EXPECT_LT(worst, 0.02);
}

TEST(BodyReadout, PausedFramesChangeNothingAndAResetStartsAgain) {
    const format::Scene scene = sceneWithBody("box.slc");
    BodyReadout readout;
    readout.update(scene, {body(0.0)}, 1.0);
    readout.update(scene, {body(1.0)}, 1.1);
    const double running = readout.rows()[0].submerged;
    EXPECT_GT(running, 0.0);
    EXPECT_LT(running, 1.0);
    for (int i = 0; i < 10; ++i)
        readout.update(scene, {body(1.0)}, 1.1); // paused: the same step read again
    EXPECT_DOUBLE_EQ(readout.rows()[0].submerged, running);
    readout.update(scene, {body(0.7)}, 0.0); // reset: the clock went back
    EXPECT_DOUBLE_EQ(readout.rows()[0].submerged, 0.7);
    readout.update(scene, {}, 0.1); // reloaded without bodies
    EXPECT_TRUE(readout.rows().empty());
}

TEST(BodyReadout, RowsNameTheAssetAndGiveMassSpeedAndContact) {
    const format::Scene scene = sceneWithBody("../meshes/crate.slc");
    BodyState moving = body(0.4);
    moving.linearVelocity = glm::vec3(0.3f, -0.4f, 0.0f);
    moving.contacts = 3;
    BodyReadout readout;
    readout.update(scene, {moving, body(0.0)}, 0.0);
    ASSERT_EQ(readout.rows().size(), 2u);
    const BodyRow& row = readout.rows()[0];
    EXPECT_EQ(row.collider, 1u);
    EXPECT_EQ(row.asset, "crate.slc");
    EXPECT_DOUBLE_EQ(row.mass, 0.25);
    EXPECT_NEAR(row.speed, 0.5, 1e-6);
    EXPECT_TRUE(row.touching);
    EXPECT_FALSE(readout.rows()[1].touching);
    EXPECT_DOUBLE_EQ(row.submerged, 0.4);
}

} // namespace
} // namespace sluice::rt
