// completeScene: a Scene built in code gets the scene reader's defaults and checks, with errors
// naming the field, and nothing changed on failure.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "sluice/format/scene/SceneDefaults.h"
#include "sluice/format/scene/SceneIO.h"

namespace sluice::test {
namespace {

using namespace sluice::format;

// A block and an emitter in a domain, every parameter left at its default.
Scene codeScene() {
    Scene scene;
    scene.path = "game";
    FluidBlock block;
    block.min = glm::vec3(0.0f);
    block.max = glm::vec3(0.2f, 0.1f, 0.2f);
    scene.blocks.push_back(block);
    Emitter nozzle;
    nozzle.position = glm::vec3(0.1f, 0.5f, 0.1f);
    nozzle.direction = glm::vec3(0.0f, -2.0f, 0.0f);
    nozzle.radius = 0.03f;
    nozzle.speed = 1.0f;
    nozzle.start = 0.5f;
    scene.emitters.push_back(nozzle);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(0.4f, 0.8f, 0.4f);
    return scene;
}

// The same scene as a file leaves every default out.
const char* kCodeSceneJson = R"({
    "fluid": [{"box": {"min": [0, 0, 0], "max": [0.2, 0.1, 0.2]}}],
    "emitters": [{"position": [0.1, 0.5, 0.1], "direction": [0, -2, 0], "radius": 0.03,
                  "speed": 1, "start": 0.5}],
    "domain": {"min": [0, 0, 0], "max": [0.4, 0.8, 0.4]}
})";

void expectSameParams(const SimulationParams& a, const SimulationParams& b) {
    EXPECT_EQ(a.spacing, b.spacing);
    EXPECT_EQ(a.kernelRadius, b.kernelRadius);
    EXPECT_EQ(a.restDensity, b.restDensity);
    EXPECT_EQ(a.timeStep, b.timeStep);
    EXPECT_EQ(a.substeps, b.substeps);
    EXPECT_EQ(a.minIterations, b.minIterations);
    EXPECT_EQ(a.maxIterations, b.maxIterations);
    EXPECT_EQ(a.targetDensityError, b.targetDensityError);
    EXPECT_EQ(a.relaxation, b.relaxation);
    EXPECT_EQ(a.scorrK, b.scorrK);
    EXPECT_EQ(a.scorrN, b.scorrN);
    EXPECT_EQ(a.scorrDeltaQ, b.scorrDeltaQ);
    EXPECT_EQ(a.xsph, b.xsph);
    EXPECT_EQ(a.vorticity, b.vorticity);
    EXPECT_EQ(a.gravity, b.gravity);
    EXPECT_EQ(a.capacity, b.capacity);
}

TEST(CompleteScene, GivesACodeBuiltSceneTheDefaultsTheReaderGivesAFile) {
    Scene scene = codeScene();
    ASSERT_TRUE(completeScene(scene)) << completeScene(scene).error().message();
    auto read = parseScene(kCodeSceneJson, "game.json", {.checkAssets = false});
    ASSERT_TRUE(read) << read.error().message();
    expectSameParams(scene.simulation, read->simulation);
    EXPECT_EQ(scene.emitters[0].direction, read->emitters[0].direction);
    EXPECT_EQ(scene.emitters[0].stop, read->emitters[0].stop);
    // The derived values themselves, so both cannot be wrong together.
    EXPECT_FLOAT_EQ(scene.simulation.kernelRadius, 0.04f);
    EXPECT_FLOAT_EQ(scene.simulation.scorrDeltaQ, 0.008f);
    EXPECT_FLOAT_EQ(scene.simulation.vorticity, float(0.01 * std::sqrt(9.81 * 0.04)));
    EXPECT_EQ(scene.emitters[0].direction, glm::vec3(0.0f, -1.0f, 0.0f));
    EXPECT_FLOAT_EQ(scene.emitters[0].stop, 10.5f);
    EXPECT_GT(scene.simulation.capacity, 10u * 5u * 10u);
}

TEST(CompleteScene, LeavesAReadSceneAsItIs) {
    auto read = parseScene(kCodeSceneJson, "game.json", {.checkAssets = false});
    ASSERT_TRUE(read) << read.error().message();
    Scene again = *read;
    ASSERT_TRUE(completeScene(again));
    expectSameParams(again.simulation, read->simulation);
}

TEST(CompleteScene, KeepsWhatTheProgramSet) {
    Scene scene = codeScene();
    scene.simulation.vorticity = 0.0f; // off, not "derive"
    scene.simulation.scorrDeltaQ = 0.0f;
    scene.simulation.substeps = 3;
    scene.simulation.capacity = 5000;
    ASSERT_TRUE(completeScene(scene));
    EXPECT_EQ(scene.simulation.vorticity, 0.0f);
    EXPECT_EQ(scene.simulation.scorrDeltaQ, 0.0f);
    EXPECT_EQ(scene.simulation.substeps, 3u);
    EXPECT_EQ(scene.simulation.capacity, 5000u);
}

TEST(CompleteScene, AcceptsAnEmptySceneWithACapacityForTheGameToFill) {
    Scene scene;
    scene.simulation.capacity = 1000;
    ASSERT_TRUE(completeScene(scene));
    EXPECT_GE(scene.simulation.substeps, 1u);
}

struct BadScene {
    const char* what;
    void (*edit)(Scene&);
    ErrorCode code;
    const char* message;
};

const float kNaN = std::numeric_limits<float>::quiet_NaN();

const BadScene kBadScenes[] = {
    {"no capacity and no fluid",
     [](Scene& s) {
         s.blocks.clear();
         s.emitters.clear();
     },
     ErrorCode::InvalidArgument, "game: simulation.capacity: 0 with no fluid blocks"},
    {"NaN spacing", [](Scene& s) { s.simulation.spacing = kNaN; }, ErrorCode::NonFinite,
     "simulation.spacing"},
    {"negative time step", [](Scene& s) { s.simulation.timeStep = -1.0f; },
     ErrorCode::InvalidArgument, "simulation.timeStep: -1 is out of range"},
    {"kernel radius past 4 spacings", [](Scene& s) { s.simulation.kernelRadius = 1.0f; },
     ErrorCode::InvalidArgument, "simulation.kernelRadius: 1 is out of range"},
    {"negative vorticity", [](Scene& s) { s.simulation.vorticity = -0.5f; },
     ErrorCode::InvalidArgument, "simulation.vorticity"},
    {"max iterations below min", [](Scene& s) { s.simulation.maxIterations = 1; },
     ErrorCode::InvalidArgument, "maxIterations 1 is less than minIterations 2"},
    {"capacity below the blocks", [](Scene& s) { s.simulation.capacity = 3; },
     ErrorCode::InvalidArgument, "simulation.capacity: 3 is smaller than the 500 particles"},
    {"inverted block", [](Scene& s) { s.blocks[0].max.y = -1.0f; }, ErrorCode::InvalidArgument,
     "fluid[0].max"},
    {"infinite block velocity",
     [](Scene& s) { s.blocks[0].velocity.x = std::numeric_limits<float>::infinity(); },
     ErrorCode::NonFinite, "fluid[0].velocity"},
    {"emitter without a direction", [](Scene& s) { s.emitters[0].direction = glm::vec3(0.0f); },
     ErrorCode::InvalidArgument, "emitters[0].direction: has no direction"},
    {"emitter stop before start", [](Scene& s) { s.emitters[0].stop = 0.25f; },
     ErrorCode::InvalidArgument, "emitters[0].stop"},
    {"half a domain", [](Scene& s) { s.domainMax.reset(); }, ErrorCode::InvalidArgument,
     "domain: needs both"},
    {"collider with a negative scale",
     [](Scene& s) {
         s.colliders.emplace_back();
         s.colliders[0].scale = -1.0f;
     },
     ErrorCode::InvalidArgument, "colliders[0].scale: -1 is out of range"},
    {"keys out of order",
     [](Scene& s) {
         s.colliders.emplace_back();
         s.colliders[0].keys = {{1.0f, {}, {}}, {0.5f, {}, {}}};
     },
     ErrorCode::InvalidArgument, "colliders[0].motion.keyframes[1].time"},
    {"body with both density and mass",
     [](Scene& s) {
         s.colliders.emplace_back();
         s.colliders[0].dynamic = DynamicBody{.density = 500.0f, .mass = 2.0f};
     },
     ErrorCode::InvalidArgument, "colliders[0].dynamic: needs exactly one"},
    {"65 colliders", [](Scene& s) { s.colliders.resize(kMaxSceneColliders + 1); },
     ErrorCode::InvalidArgument, "colliders: 65 colliders"},
    {"an inverted drain",
     [](Scene& s) {
         s.drains.push_back({{0.0f, 1.0f, 0.0f}, {1.0f, 0.5f, 1.0f}});
     },
     ErrorCode::InvalidArgument, "drains: [0].box.max"},
    {"nine drains",
     [](Scene& s) {
         s.drains.resize(9, {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}});
     },
     ErrorCode::InvalidArgument, "9 drains, more than the limit 8"},
};

TEST(CompleteScene, RefusesEachBadFieldByNameAndChangesNothing) {
    for (const BadScene& bad : kBadScenes) {
        SCOPED_TRACE(bad.what);
        Scene scene = codeScene();
        bad.edit(scene);
        const Scene before = scene;
        auto ok = completeScene(scene);
        ASSERT_FALSE(ok);
        EXPECT_EQ(ok.error().code, bad.code);
        EXPECT_NE(ok.error().detail.find(bad.message), std::string::npos) << ok.error().detail;
        EXPECT_EQ(scene.simulation.kernelRadius, before.simulation.kernelRadius);
        EXPECT_EQ(scene.simulation.capacity, before.simulation.capacity);
        EXPECT_EQ(scene.simulation.vorticity, before.simulation.vorticity);
        EXPECT_EQ(scene.emitters.size() > 0 ? scene.emitters[0].direction : glm::vec3(0.0f),
                  before.emitters.size() > 0 ? before.emitters[0].direction : glm::vec3(0.0f));
    }
}

TEST(SceneReader, ReadsDrainsAndRefusesBadOnes) {
    auto read = parseScene(R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
        "drains": [{"box": {"min": [0.5, 0, 0], "max": [0.6, 0.2, 0.1]}}]})",
                           "d.json", {.checkAssets = false});
    ASSERT_TRUE(read) << read.error().message();
    ASSERT_EQ(read->drains.size(), 1u);
    EXPECT_EQ(read->drains[0].min, glm::vec3(0.5f, 0.0f, 0.0f));
    EXPECT_EQ(read->drains[0].max, glm::vec3(0.6f, 0.2f, 0.1f));
    auto bad = parseScene(R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
        "drains": [{"box": {"min": [0.5, 0, 0], "max": [0.4, 0.2, 0.1]}}]})",
                          "d.json", {.checkAssets = false});
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().detail.find("d.json: drains[0].box.max"), std::string::npos)
        << bad.error().detail;
    auto unknown = parseScene(R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
        "drains": [{"sphere": {}}]})",
                              "d.json", {.checkAssets = false});
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.error().code, ErrorCode::BadMetadata);
}

} // namespace
} // namespace sluice::test
