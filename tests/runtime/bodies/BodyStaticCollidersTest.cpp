// Bodies against static colliders wherever the scene lists them: the passes find the static
// colliders by a 32-bit mask, then walk the colliders past the 32nd (PbfGlsl.h,
// nextStaticCollider).
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "bodies/BodyTank.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;
using namespace bodytest;

class BodyStaticColliders : public GpuTest {};

TEST_F(BodyStaticColliders, ABodyRestsOnAStaticColliderListedPastThe32nd) {
    // The passes find the static colliders by a 32-bit mask and then walk the colliders past
    // the 32nd (nextStaticCollider in PbfGlsl.h). 32 small static boxes out of reach come
    // first, so the pedestal is collider 32: the tilted box must settle on it, not fall through
    // it to the floor.
    format::Scene scene = testscene::emptyScene(kSpacing, 8, 16);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(0.6f, 0.5f, 0.4f);
    for (int i = 0; i < 32; ++i) {
        format::SceneCollider filler;
        filler.asset = "cube.slc";
        filler.scale = 0.1f;
        filler.translation = glm::vec3(0.02f + 0.018f * float(i), 0.05f * kSide, 0.38f);
        scene.colliders.push_back(filler);
    }
    addPedestalAndTiltedBox(scene);
    std::vector<format::ColliderAsset> assets(scene.colliders.size(), cubeAsset(kSide));
    auto sim = Simulation::create(scene, std::move(assets));
    ASSERT_TRUE(sim) << sim.error().message();
    for (int step = 0; step < 30; ++step)
        sim->step();
    const BodyState box = sim->bodies().at(0);
    std::printf("box on collider 32: centre %.5f m (on the pedestal: %.5f m), %u contacts\n",
                box.position.y, 1.5 * kSide, box.contacts);
    EXPECT_NEAR(box.position.y, 1.5 * kSide, 0.25 * kSpacing) << "it rests on the pedestal";
    EXPECT_GT(box.contacts, 0u);
    EXPECT_TRUE(finite(box));
}

} // namespace
} // namespace sluice::rt
