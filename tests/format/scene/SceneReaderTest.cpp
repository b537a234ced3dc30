// The scene reader: shipped scenes, derived defaults and what it reads. The dynamic colliders' keys
// are in SceneReaderDynamicTest.cpp, every kind of error it reports in SceneReaderErrorsTest.cpp.
#include <gtest/gtest.h>

#include "SceneReaderTestUtil.h"

namespace sluice::test {
namespace {

using namespace sluice::format;
using namespace scenetest;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Shipped scenes

TEST(SceneReader, ParsesEveryShippedScene) {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(kAssetsDir)) {
        if (entry.path().extension() != ".json")
            continue;
        names.insert(entry.path().stem().string());
        auto r = readScene(entry.path(), kNoAssetCheck);
        ASSERT_TRUE(r.ok()) << r.error().message();
        const Scene& s = *r;
        SCOPED_TRACE(s.path);
        EXPECT_EQ(s.name, entry.path().stem().string());
        EXPECT_GE(s.simulation.spacing, 0.02f);
        EXPECT_LE(s.simulation.spacing, 0.03f);
        EXPECT_GT(s.simulation.capacity, 1000u);
        EXPECT_LT(s.simulation.capacity, 15000u);
        EXPECT_GE(s.simulation.substeps, 1u);
        EXPECT_LE(s.simulation.substeps, 8u);
        EXPECT_TRUE(s.camera.set);
        EXPECT_TRUE(s.domainMin.has_value());
        for (const SceneCollider& c : s.colliders)
            EXPECT_EQ(fs::path(c.resolvedPath), (kAssetsDir / c.asset).lexically_normal());
    }
    const std::set<std::string> expected{"dam-break", "drop", "funnel", "martin-moyce",
                                         "wave-sphere"};
    for (const std::string& name : expected)
        EXPECT_TRUE(names.count(name)) << name << ".json missing from assets/";
}

/// The names in a comma-separated list.
static std::vector<std::string> sceneList(const std::string& text) {
    std::vector<std::string> names;
    std::stringstream list(text);
    for (std::string name; std::getline(list, name, ',');)
        if (!name.empty())
            names.push_back(name);
    return names;
}

/// The scenes the build copies next to its baked colliders (assets/CMakeLists.txt), by name.
static std::vector<std::string> builtScenes() {
    return sceneList(SLUICE_BUILT_SCENES);
}

TEST(SceneReader, TheBuildCopiesEveryShippedScene) {
    std::set<std::string> shipped;
    for (const auto& entry : fs::directory_iterator(kAssetsDir))
        if (entry.path().extension() == ".json")
            shipped.insert(entry.path().filename().string());
    const std::vector<std::string> built = builtScenes();
    EXPECT_EQ(std::set<std::string>(built.begin(), built.end()), shipped);
}

TEST(SceneReader, FindsTheBakedCollidersOfTheBuiltScenes) {
    // The build copies the scenes next to the colliders it bakes (assets/CMakeLists.txt). Other
    // files may lie beside them (a user's own outputs): only the built scenes are read.
    const fs::path built(SLUICE_BUILD_ASSETS_DIR);
    if (!fs::exists(built / "tank.slc") || !fs::exists(built / "funnel.json"))
        GTEST_SKIP() << "no baked colliders in " << built << " yet (build sluice_assets)";
    const std::vector<std::string> names = builtScenes();
    ASSERT_GE(names.size(), 5u);
    // Scenes whose collider this preset does not bake (the terrain under the sanitizers).
    const std::vector<std::string> unbaked = sceneList(SLUICE_UNBAKED_SCENES);
    for (const std::string& name : names) {
        if (std::find(unbaked.begin(), unbaked.end(), name) != unbaked.end())
            continue;
        auto r = readScene(built / name);
        EXPECT_TRUE(r.ok()) << r.error().message();
    }
}

TEST(SceneReader, ShippedScenesHoldTheParticleCountsTheirDescriptionsGive) {
    auto capacity = [](const char* name) {
        auto r = readScene(kAssetsDir / name, kNoAssetCheck);
        EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message());
        return r.ok() ? r->simulation.capacity : 0u;
    };
    // 10 x 20 x 10 column; 15 x 15 x 21 block; 400 layers of a 13-point disc; pool + ball.
    EXPECT_EQ(capacity("martin-moyce.json"), 2000u);
    EXPECT_LT(capacity("martin-moyce.json"), 8000u);
    EXPECT_EQ(capacity("dam-break.json"), 4725u);
    EXPECT_EQ(capacity("wave-sphere.json"), 4725u);
    EXPECT_EQ(capacity("funnel.json"), 5200u);
    EXPECT_EQ(capacity("drop.json"), 36u * 4u * 21u + bruteSphere(0.12, 0.02));
    // A 36 x 8 x 21 pool; the dam-break block + a 21 x 6 x 21 pool (before the crates take
    // their share out at the start).
    EXPECT_EQ(capacity("float.json"), 36u * 8u * 21u);
    EXPECT_EQ(capacity("crates.json"), 4725u + 21u * 6u * 21u);
}

TEST(SceneReader, ShippedMartinMoyceIsAQuasi2dColumnInTheDomainCorner) {
    auto r = readScene(kAssetsDir / "martin-moyce.json", kNoAssetCheck);
    ASSERT_TRUE(r.ok()) << r.error().message();
    ASSERT_EQ(r->blocks.size(), 1u);
    const FluidBlock& b = r->blocks[0];
    const float a = b.max.x - b.min.x;
    EXPECT_FLOAT_EQ(b.max.y - b.min.y, 2 * a);
    EXPECT_FLOAT_EQ(b.max.z - b.min.z, a);
    EXPECT_EQ(b.min, *r->domainMin);
    EXPECT_FLOAT_EQ(r->domainMax->z - r->domainMin->z, a);
    EXPECT_GE(r->domainMax->x - r->domainMin->x, 4 * a);
    EXPECT_TRUE(r->colliders.empty());
}

// ---------------------------------------------------------------------------------------------
// Defaults

TEST(SceneReader, DerivesDefaultsFromTheSpacing) {
    const Scene s = parseOk(
        R"({"simulation": {"spacing": 0.03},
            "fluid": [{"box": {"min": [0, 0, 0], "max": [0.3, 0.3, 0.3]}}]})");
    const SimulationParams& p = s.simulation;
    const float h = 2.0f * 0.03f;
    EXPECT_FLOAT_EQ(p.spacing, 0.03f);
    EXPECT_FLOAT_EQ(p.kernelRadius, h);
    EXPECT_EQ(p.maxIterations, 8u);
    EXPECT_EQ(p.minIterations, 2u);
    EXPECT_FLOAT_EQ(p.relaxation, 0.01f);
    EXPECT_FLOAT_EQ(p.scorrK, 0.1f);
    EXPECT_FLOAT_EQ(p.scorrN, 4.0f);
    EXPECT_FLOAT_EQ(p.scorrDeltaQ, 0.2f * h);
    EXPECT_FLOAT_EQ(p.vorticity, float(0.01 * std::sqrt(9.81 * h)));
    EXPECT_FLOAT_EQ(p.xsph, 0.01f);
    EXPECT_FLOAT_EQ(p.restDensity, 1000.0f);
    EXPECT_FLOAT_EQ(p.timeStep, 1.0f / 60.0f);
    EXPECT_FLOAT_EQ(p.targetDensityError, 0.005f);
    EXPECT_EQ(p.gravity, glm::vec3(0.0f, -9.81f, 0.0f));
    EXPECT_EQ(p.capacity, 10u * 10u * 10u);
    // H = 0.3 m: v = sqrt(2 g H); substeps = ceil(dt v / (0.4 h)).
    const double v = std::sqrt(2.0 * 9.81 * 0.3);
    EXPECT_EQ(p.substeps, std::uint32_t(std::ceil((1.0 / 60.0) * v / (0.4 * h))));
    EXPECT_EQ(s.name, "scene");
    EXPECT_EQ(s.path, "scene.json");
    EXPECT_FALSE(s.camera.set);
    EXPECT_FALSE(s.domainMin.has_value());
}

TEST(SceneReader, KeepsEveryExplicitSimulationValue) {
    const Scene s = parseOk(withSimulation(
        R"("spacing": 0.05, "kernelRadius": 0.15, "restDensity": 998, "timeStep": 0.01,
           "substeps": 7, "minIterations": 3, "maxIterations": 12, "targetDensityError": 0.02,
           "relaxation": 0, "scorrK": 0, "scorrN": 2, "scorrDeltaQ": 0, "xsph": 0.5,
           "vorticity": 0, "gravity": [0, 0, -3], "capacity": 100)"));
    const SimulationParams& p = s.simulation;
    EXPECT_FLOAT_EQ(p.spacing, 0.05f);
    EXPECT_FLOAT_EQ(p.kernelRadius, 0.15f);
    EXPECT_FLOAT_EQ(p.restDensity, 998.0f);
    EXPECT_FLOAT_EQ(p.timeStep, 0.01f);
    EXPECT_EQ(p.substeps, 7u);
    EXPECT_EQ(p.minIterations, 3u);
    EXPECT_EQ(p.maxIterations, 12u);
    EXPECT_FLOAT_EQ(p.targetDensityError, 0.02f);
    EXPECT_EQ(p.relaxation, 0.0f); // explicit zeros are kept, not replaced by defaults
    EXPECT_EQ(p.scorrK, 0.0f);
    EXPECT_FLOAT_EQ(p.scorrN, 2.0f);
    EXPECT_EQ(p.scorrDeltaQ, 0.0f);
    EXPECT_FLOAT_EQ(p.xsph, 0.5f);
    EXPECT_EQ(p.vorticity, 0.0f);
    EXPECT_EQ(p.gravity, glm::vec3(0, 0, -3));
    EXPECT_EQ(p.capacity, 100u);
}

TEST(SceneReader, ReadsTheBoundaryModelNotesTheRemovedOneAndRefusesAnUnknownOne) {
    EXPECT_FALSE(parseOk(kMinimal).namesRemovedBoundaryModel);
    EXPECT_FALSE(parseOk(withSimulation(R"("boundary": "solids")")).namesRemovedBoundaryModel);
    // "bodies" was removed: the scene still reads (sluice-play warns), with the one model.
    EXPECT_TRUE(parseOk(withSimulation(R"("boundary": "bodies")")).namesRemovedBoundaryModel);
    expectError(withSimulation(R"("boundary": "walls")"), ErrorCode::InvalidArgument,
                {"simulation.boundary", "unknown boundary model \"walls\"", "\"solids\""});
    expectError(withSimulation(R"("boundary": true)"), ErrorCode::BadMetadata,
                {"simulation.boundary", "expected a string"});
}

TEST(SceneReader, DerivesTheScorrDeltaQAndVorticityFromAnExplicitKernelRadius) {
    const Scene s = parseOk(withSimulation(R"("spacing": 0.01, "kernelRadius": 0.035)"));
    EXPECT_FLOAT_EQ(s.simulation.scorrDeltaQ, 0.2f * 0.035f);
    EXPECT_FLOAT_EQ(s.simulation.vorticity, float(0.01 * std::sqrt(9.81 * 0.035)));
}

TEST(SceneReader, DerivesSubstepsFromTheFastestLikelySpeed) {
    // Box 1 m tall moving at 3 m/s: v = 3 + sqrt(2 g 1).
    const Scene a = parseOk(R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 1, 0.1]},
                                             "velocity": [0, 0, 3]}]})");
    const double h = 0.04;
    const double va = 3.0 + std::sqrt(2.0 * 9.81 * 1.0);
    EXPECT_EQ(a.simulation.substeps, std::uint32_t(std::ceil((1.0 / 60.0) * va / (0.4 * h))));

    // An emitter at y = 2 over a domain from y = 0: H = 2, v = speed + sqrt(2 g H).
    const Scene b = parseOk(R"({"emitters": [{"position": [0, 2, 0], "direction": [0, -1, 0],
                                               "radius": 0.04, "speed": 1.5}],
                                "domain": {"min": [-1, 0, -1], "max": [1, 1, 1]}})");
    const double vb = 1.5 + std::sqrt(2.0 * 9.81 * 2.0);
    EXPECT_EQ(b.simulation.substeps, std::uint32_t(std::ceil((1.0 / 60.0) * vb / (0.4 * h))));

    // No gravity, nothing moving: one substep. A very fast nozzle: capped at 64.
    EXPECT_EQ(parseOk(withSimulation(R"("gravity": [0, 0, 0])")).simulation.substeps, 1u);
    EXPECT_EQ(parseOk(withEmitter({{"speed", "1000"}, {"stop", "0.01"}})).simulation.substeps, 64u);
}

TEST(SceneReader, SizesTheCapacityForBlocksAndEverythingEmittersEmit) {
    // Disc of radius 0.04 at spacing 0.02: 13 points; interval 0.02 / 1 s: from 1 s to 3 s,
    // 100 layers.
    const Scene a = parseOk(withEmitter({{"start", "1"}, {"stop", "3"}}));
    EXPECT_EQ(emitterDiscCount(0.04f, 0.02f), 13u);
    EXPECT_EQ(a.simulation.capacity, 100u * 13u);
    // Default stop: start + 10 s, 500 layers.
    const Scene b = parseOk(withEmitter());
    EXPECT_FLOAT_EQ(b.emitters[0].stop, 10.0f);
    EXPECT_EQ(b.simulation.capacity, 500u * 13u);
    // A rate cap of 100 particles/s: interval max(0.02, 13 / 100) = 0.13 s, ceil(2 / 0.13) = 16.
    const Scene c = parseOk(withEmitter({{"rate", "100"}, {"start", "1"}, {"stop", "3"}}));
    EXPECT_EQ(c.simulation.capacity, 16u * 13u);
    // Blocks and emitters add up.
    const Scene d = parseOk(R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
                                "emitters": [{"position": [0, 1, 0], "direction": [0, -1, 0],
                                              "radius": 0.04, "speed": 1, "stop": 2}]})");
    EXPECT_EQ(d.simulation.capacity, 125u + 100u * 13u);
}

TEST(SceneReader, CountsBlockParticlesByTheLatticeRule) {
    FluidBlock box;
    box.min = {0.0f, 0.0f, 0.0f};
    box.max = {0.2f, 0.4f, 0.2f};
    EXPECT_EQ(blockParticleCount(box, 0.02f), 10u * 20u * 10u);
    box.max = {0.219f, 0.4f, 0.2f}; // 10.95 spacings: still 10
    EXPECT_EQ(blockParticleCount(box, 0.02f), 10u * 20u * 10u);
    box.max = {0.019f, 0.4f, 0.2f}; // thinner than a spacing
    EXPECT_EQ(blockParticleCount(box, 0.02f), 0u);
    FluidBlock ball;
    ball.shape = FluidBlock::Shape::Sphere;
    // Radii whose lattice boundary falls between points, so double and float agree.
    for (const float r : {0.0101f, 0.055f, 0.12f, 0.215f, 0.335f}) {
        ball.radius = r;
        EXPECT_EQ(blockParticleCount(ball, 0.02f), bruteSphere(r, 0.02)) << "radius " << r;
    }
    ball.radius = 0.01f; // exactly spacing / 2: the centre only
    EXPECT_EQ(blockParticleCount(ball, 0.02f), 1u);
    ball.radius = 0.009f; // below spacing / 2: not even the centre
    EXPECT_EQ(blockParticleCount(ball, 0.02f), 0u);
    for (const float r : {0.01f, 0.03f, 0.045f, 0.11f, 0.51f})
        EXPECT_EQ(emitterDiscCount(r, 0.02f), bruteDisc(r, 0.02)) << "radius " << r;
    // Shapes far over the limit are reported as over it without being enumerated.
    box.max = {1000.0f, 1000.0f, 1000.0f};
    EXPECT_GT(blockParticleCount(box, 1e-4f), std::uint64_t(kMaxSceneParticles));
    ball.radius = 1000.0f;
    EXPECT_GT(blockParticleCount(ball, 1e-4f), std::uint64_t(kMaxSceneParticles));
    EXPECT_GT(emitterDiscCount(1000.0f, 1e-4f), std::uint64_t(kMaxSceneParticles));
}

// ---------------------------------------------------------------------------------------------
// Contents

TEST(SceneReader, ReadsBlocksEmittersCollidersDomainAndCamera) {
    const Scene s = parseOk(R"({
        "name": "everything", "description": "ignored",
        "fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}, "velocity": [1, 2, 3]},
                  {"sphere": {"center": [1, 1, 1], "radius": 0.1}}],
        "emitters": [{"position": [0, 1, 0], "direction": [3, 0, 4], "radius": 0.04, "speed": 2,
                      "rate": 500, "start": 0.5, "stop": 1.5}],
        "colliders": [{"asset": "sub/tank.slc", "translation": [1, 2, 3], "rotation": [10, 20, 30],
                       "scale": 2, "friction": 0.25,
                       "motion": {"linearVelocity": [0, 1, 0], "angularVelocity": [0, 90, 0]}},
                      {"asset": "ball.slc", "motion": {"keyframes": [
                          {"time": 0, "translation": [0, 0, 0]},
                          {"time": 1.5, "translation": [1, 0, 0], "rotation": [0, 45, 0]}]}}],
        "domain": {"min": [-1, 0, -1], "max": [2, 3, 2]},
        "camera": {"position": [3, 2, 1], "target": [0, 0.5, 0], "fov": 60}
    })");
    EXPECT_EQ(s.name, "everything");
    ASSERT_EQ(s.blocks.size(), 2u);
    EXPECT_EQ(s.blocks[0].shape, FluidBlock::Shape::Box);
    EXPECT_EQ(s.blocks[0].velocity, glm::vec3(1, 2, 3));
    EXPECT_EQ(s.blocks[1].shape, FluidBlock::Shape::Sphere);
    EXPECT_EQ(s.blocks[1].center, glm::vec3(1, 1, 1));
    EXPECT_FLOAT_EQ(s.blocks[1].radius, 0.1f);
    ASSERT_EQ(s.emitters.size(), 1u);
    const Emitter& e = s.emitters[0];
    EXPECT_FLOAT_EQ(e.direction.x, 0.6f); // normalised
    EXPECT_FLOAT_EQ(e.direction.z, 0.8f);
    EXPECT_FLOAT_EQ(e.rate, 500.0f);
    EXPECT_FLOAT_EQ(e.start, 0.5f);
    EXPECT_FLOAT_EQ(e.stop, 1.5f);
    ASSERT_EQ(s.colliders.size(), 2u);
    const SceneCollider& c = s.colliders[0];
    EXPECT_EQ(c.asset, "sub/tank.slc");
    EXPECT_EQ(c.resolvedPath, "sub/tank.slc"); // scene.json lies in the current folder
    EXPECT_EQ(c.translation, glm::vec3(1, 2, 3));
    EXPECT_EQ(c.rotationDegrees, glm::vec3(10, 20, 30));
    EXPECT_FLOAT_EQ(c.scale, 2.0f);
    EXPECT_FLOAT_EQ(c.friction, 0.25f);
    EXPECT_EQ(c.linearVelocity, glm::vec3(0, 1, 0));
    EXPECT_EQ(c.angularVelocityDegrees, glm::vec3(0, 90, 0));
    EXPECT_TRUE(c.keys.empty());
    ASSERT_EQ(s.colliders[1].keys.size(), 2u);
    EXPECT_FLOAT_EQ(s.colliders[1].keys[1].time, 1.5f);
    EXPECT_EQ(s.colliders[1].keys[1].translation, glm::vec3(1, 0, 0));
    EXPECT_EQ(s.colliders[1].keys[1].rotationDegrees, glm::vec3(0, 45, 0));
    EXPECT_EQ(*s.domainMin, glm::vec3(-1, 0, -1));
    EXPECT_EQ(*s.domainMax, glm::vec3(2, 3, 2));
    EXPECT_TRUE(s.camera.set);
    EXPECT_EQ(s.camera.position, glm::vec3(3, 2, 1));
    EXPECT_FLOAT_EQ(s.camera.fovDegrees, 60.0f);
}

TEST(SceneReader, AcceptsIntegralNumbersWrittenAsDecimalsAndAByteOrderMark) {
    const Scene s = parseOk("\xEF\xBB\xBF" + withSimulation(R"("substeps": 4.0, "capacity": 2e3)"));
    EXPECT_EQ(s.simulation.substeps, 4u);
    EXPECT_EQ(s.simulation.capacity, 2000u);
}

TEST(SceneReader, ResolvesColliderAssetsAgainstTheSceneFolder) {
    BuildTempDir dir;
    fs::create_directories(dir.path() / "colliders");
    dir.write("colliders/tank.slc", "not checked for content here");
    // colliders[0] is "a.slc", missing; colliders[1] exists.
    const fs::path file = dir.write("scene.json", withCollider(R"("asset": "colliders/tank.slc")"));
    const std::string json = R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
                                 "colliders": [{"asset": "colliders/tank.slc"}]})";
    const fs::path ok = dir.write("ok.json", json);
    auto r = readScene(ok);
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_EQ(fs::path(r->colliders[0].resolvedPath), dir.path() / "colliders" / "tank.slc");
    EXPECT_EQ(r->name, "ok");
    EXPECT_EQ(r->path, ok.string());

    auto missing = readScene(file);
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::Io);
    const std::string& m = missing.error().detail;
    EXPECT_NE(m.find(file.string() + ": colliders[0].asset: collider asset not found: " +
                     (dir.path() / "a.slc").string() + " (bake it with sluice-bake)"),
              std::string::npos)
        << m;
    EXPECT_TRUE(readScene(file, kNoAssetCheck).ok());
}

TEST(SceneReader, RejectsAColliderAssetThatIsAFolder) {
    BuildTempDir dir;
    fs::create_directories(dir.path() / "a.slc");
    const fs::path file = dir.write("scene.json", R"({"emitters": [], "fluid": [
        {"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}], "colliders": [{"asset": "a.slc"}]})");
    auto r = readScene(file);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::Io);
    EXPECT_NE(r.error().detail.find("colliders[0].asset: collider asset is not a file"),
              std::string::npos)
        << r.error().detail;
}

} // namespace
} // namespace sluice::test
