// The scene reader: shipped scenes, derived defaults, and every kind of error it reports.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "asset/AssetTestUtil.h" // PrintTo(ErrorCode)
#include "sluice/format/scene/SceneIO.h"

namespace sluice::test {
namespace {

using namespace sluice::format;
namespace fs = std::filesystem;

const fs::path kAssetsDir = fs::path(SLUICE_SOURCE_DIR) / "assets";
const SceneReadOptions kNoAssetCheck{.checkAssets = false};

// A folder under the build tree, unique to this process and test, removed afterwards.
class BuildTempDir {
public:
    BuildTempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_path = fs::path(SLUICE_TEST_TMP_DIR) /
                 (std::string(info ? info->name() : "scene") + "-" + std::to_string(::getpid()));
        fs::remove_all(m_path);
        fs::create_directories(m_path);
    }
    BuildTempDir(const BuildTempDir&) = delete;
    BuildTempDir& operator=(const BuildTempDir&) = delete;
    ~BuildTempDir() {
        std::error_code ec;
        fs::remove_all(m_path, ec);
    }
    fs::path write(const std::string& name, const std::string& text) const {
        const fs::path p = m_path / name;
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
    const fs::path& path() const { return m_path; }

private:
    fs::path m_path;
};

// One box of 5 x 5 x 5 particles at the default spacing 0.02.
const std::string kMinimal = R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}]})";

Scene parseOk(const std::string& json, const SceneReadOptions& options = kNoAssetCheck) {
    auto r = parseScene(json, "scene.json", options);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message()) << "\n" << json;
    return r.ok() ? std::move(r).value() : Scene{};
}

// Parses `json` as scene.json, expects `code` and a message holding the file name and every
// one of `parts` (the JSON path, the problem).
void expectError(const std::string& json, ErrorCode code, const std::vector<std::string>& parts,
                 const SceneReadOptions& options = kNoAssetCheck) {
    const auto r = parseScene(json, "scene.json", options);
    ASSERT_FALSE(r.ok()) << "accepted:\n" << json;
    EXPECT_EQ(r.error().code, code) << r.error().message() << "\n" << json;
    const std::string& m = r.error().detail;
    EXPECT_EQ(m.rfind("scene.json", 0), 0u) << m;
    for (const std::string& part : parts)
        EXPECT_NE(m.find(part), std::string::npos) << "'" << part << "' not in: " << m;
}

// The minimal scene with `simulation` set to the given object body.
std::string withSimulation(const std::string& body) {
    return R"({"simulation": {)" + body +
           R"(}, "fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}]})";
}

// The minimal scene plus one collider with the given object body.
std::string withCollider(const std::string& body) {
    return R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
               "colliders": [{"asset": "a.slc"}, {)" +
           body + "}]}";
}

// The minimal scene plus a static collider and colliders[1], "b.slc", with "dynamic" set to
// the given object body and `more` (keys of the collider itself, each with a leading comma).
std::string withDynamic(const std::string& body, const std::string& more = {}) {
    return withCollider(R"("asset": "b.slc", "dynamic": {)" + body + "}" + more);
}

// A scene of one emitter: position [0, 1, 0], direction [0, -1, 0], radius 0.04, speed 1, with
// `changes` replacing or adding keys (a value of "" removes the key).
std::string withEmitter(const std::vector<std::pair<std::string, std::string>>& changes = {}) {
    std::vector<std::pair<std::string, std::string>> keys = {
        {"position", "[0, 1, 0]"}, {"direction", "[0, -1, 0]"}, {"radius", "0.04"}, {"speed", "1"}};
    for (const auto& change : changes) {
        auto it = std::find_if(keys.begin(), keys.end(),
                               [&](const auto& k) { return k.first == change.first; });
        if (it == keys.end())
            keys.push_back(change);
        else
            it->second = change.second;
    }
    std::string body;
    for (const auto& [key, value] : keys)
        if (!value.empty())
            body += (body.empty() ? "\"" : ", \"") + key + "\": " + value;
    return R"({"emitters": [{)" + body + "}]}";
}

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Brute-force lattice counts from docs/pbf.md, in double, to check the reader's own.
std::uint64_t bruteSphere(double radius, double s) {
    const double reach = radius - s / 2;
    const int k = int(std::ceil(reach / s)) + 1;
    std::uint64_t n = 0;
    for (int i = -k; i <= k; ++i)
        for (int j = -k; j <= k; ++j)
            for (int l = -k; l <= k; ++l)
                n += s * std::sqrt(double(i * i + j * j + l * l)) <= reach;
    return n;
}

std::uint64_t bruteDisc(double radius, double s) {
    const int k = int(radius / s) + 2;
    std::uint64_t n = 0;
    for (int a = -k; a <= k; ++a)
        for (int b = -k; b <= k; ++b)
            n += s * s * (a * a + b * b) <= radius * radius;
    return n;
}

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

TEST(SceneReader, ReadsTheBoundaryModelAndRefusesAnUnknownOne) {
    EXPECT_FALSE(parseOk(kMinimal).simulation.solidBoundary) << "the default is \"bodies\"";
    EXPECT_TRUE(parseOk(withSimulation(R"("boundary": "solids")")).simulation.solidBoundary);
    EXPECT_FALSE(parseOk(withSimulation(R"("boundary": "bodies")")).simulation.solidBoundary);
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

// ---------------------------------------------------------------------------------------------
// Dynamic colliders

TEST(SceneReader, ReadsEveryKeyOfADynamicColliderInTheDensityForm) {
    const Scene s = parseOk(withDynamic(R"("density": 500, "linearVelocity": [1, -2, 3],
                                           "angularVelocity": [0, 90, -45], "friction": 1.5,
                                           "restitution": 0.25)",
                                        R"(, "translation": [0, 0.5, 0], "friction": 0.75)"));
    ASSERT_EQ(s.colliders.size(), 2u);
    EXPECT_FALSE(s.colliders[0].dynamic.has_value()); // a collider without the key stays static
    const SceneCollider& c = s.colliders[1];
    ASSERT_TRUE(c.dynamic.has_value());
    const DynamicBody& d = *c.dynamic;
    ASSERT_TRUE(d.density.has_value());
    EXPECT_FLOAT_EQ(*d.density, 500.0f);
    EXPECT_FALSE(d.mass.has_value());
    EXPECT_EQ(d.linearVelocity, glm::vec3(1, -2, 3));
    EXPECT_EQ(d.angularVelocityDegrees, glm::vec3(0, 90, -45)); // kept in degrees/s
    EXPECT_FLOAT_EQ(d.friction, 1.5f);
    EXPECT_FLOAT_EQ(d.restitution, 0.25f);
    // The collider's own keys are read as for any collider; the body's initial velocities are
    // not copied into the kinematic ones, which stay zero.
    EXPECT_EQ(c.translation, glm::vec3(0, 0.5f, 0));
    EXPECT_FLOAT_EQ(c.friction, 0.75f);
    EXPECT_EQ(c.linearVelocity, glm::vec3(0));
    EXPECT_EQ(c.angularVelocityDegrees, glm::vec3(0));
    EXPECT_TRUE(c.keys.empty());
}

TEST(SceneReader, ReadsADynamicColliderInTheMassFormWithDefaults) {
    const Scene s = parseOk(withDynamic(R"("mass": 2.5)"));
    ASSERT_TRUE(s.colliders[1].dynamic.has_value());
    const DynamicBody& d = *s.colliders[1].dynamic;
    ASSERT_TRUE(d.mass.has_value());
    EXPECT_FLOAT_EQ(*d.mass, 2.5f);
    EXPECT_FALSE(d.density.has_value());
    EXPECT_FLOAT_EQ(d.friction, 0.5f);
    EXPECT_EQ(d.restitution, 0.0f);
    EXPECT_EQ(d.linearVelocity, glm::vec3(0));
    EXPECT_EQ(d.angularVelocityDegrees, glm::vec3(0));

    // The ends of the friction and restitution ranges are allowed.
    const Scene ends = parseOk(withDynamic(R"("density": 1e-3, "friction": 2, "restitution": 1)"));
    EXPECT_FLOAT_EQ(*ends.colliders[1].dynamic->density, 1e-3f);
    EXPECT_FLOAT_EQ(ends.colliders[1].dynamic->friction, 2.0f);
    EXPECT_FLOAT_EQ(ends.colliders[1].dynamic->restitution, 1.0f);
    const Scene zeros = parseOk(withDynamic(R"("mass": 1, "friction": 0, "restitution": 0)"));
    EXPECT_EQ(zeros.colliders[1].dynamic->friction, 0.0f); // an explicit 0 is kept
}

TEST(SceneReader, RejectsADynamicDensityOfZeroWithTheExactMessage) {
    const auto r = parseScene(withDynamic(R"("density": 0)"), "scene.json", kNoAssetCheck);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(r.error().detail, "scene.json: colliders[1].dynamic.density: 0 is out of range: "
                                "must be > 0");
}

TEST(SceneReader, RejectsDynamicValuesOutOfRangeNamingTheRange) {
    struct Case {
        std::string json;
        std::string part;
    };
    const std::vector<Case> cases = {
        {withDynamic(R"("density": -5)"),
         "colliders[1].dynamic.density: -5 is out of range: must be > 0"},
        {withDynamic(R"("density": -0.0)"),
         "colliders[1].dynamic.density: -0 is out of range: must be > 0"},
        {withDynamic(R"("mass": 0)"), "colliders[1].dynamic.mass: 0 is out of range: must be > 0"},
        {withDynamic(R"("mass": -1)"),
         "colliders[1].dynamic.mass: -1 is out of range: must be > 0"},
        {withDynamic(R"("density": 500, "friction": 2.5)"),
         "colliders[1].dynamic.friction: 2.5 is out of range [0, 2]"},
        {withDynamic(R"("density": 500, "friction": -0.5)"),
         "colliders[1].dynamic.friction: -0.5 is out of range [0, 2]"},
        {withDynamic(R"("density": 500, "restitution": -0.1)"),
         "colliders[1].dynamic.restitution: -0.1 is out of range [0, 1]"},
        {withDynamic(R"("mass": 1, "restitution": 1.01)"),
         "colliders[1].dynamic.restitution: 1.01 is out of range [0, 1]"},
        // The collider's own friction keeps its own range next to a body's.
        {withDynamic(R"("density": 500, "friction": 2)", R"(, "friction": 1.5)"),
         "colliders[1].friction: 1.5 is out of range [0, 1]"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.json);
        expectError(c.json, ErrorCode::InvalidArgument, {c.part});
    }
}

TEST(SceneReader, RejectsNonFiniteAndHugeDynamicValuesNamingThePath) {
    expectError(withDynamic(R"("density": NaN)"), ErrorCode::NonFinite,
                {"colliders[1].dynamic.density: NaN is not a finite number"});
    expectError(withDynamic(R"("density": Infinity)"), ErrorCode::NonFinite,
                {"colliders[1].dynamic.density: Infinity is not a finite number"});
    expectError(withDynamic(R"("density": 1e39)"), ErrorCode::NonFinite,
                {"colliders[1].dynamic.density: 1e+39 is not finite as a 32-bit float"});
    expectError(withDynamic(R"("mass": -Infinity)"), ErrorCode::NonFinite,
                {"colliders[1].dynamic.mass: -Infinity is not a finite number"});
    expectError(withDynamic(R"("mass": 1, "linearVelocity": [0, NaN, 0])"), ErrorCode::NonFinite,
                {"colliders[1].dynamic.linearVelocity[1]: NaN is not a finite number"});
    expectError(withDynamic(R"("mass": 1, "angularVelocity": [0, 0, 1e39])"), ErrorCode::NonFinite,
                {"colliders[1].dynamic.angularVelocity[2]: 1e+39 is not finite as a 32-bit "
                 "float"});
    expectError(withDynamic(R"("mass": 1, "restitution": Inf)"), ErrorCode::NonFinite,
                {"colliders[1].dynamic.restitution: Infinity is not a finite number"});
}

TEST(SceneReader, RejectsADynamicColliderWithBothOrNeitherOfDensityAndMass) {
    const std::string problem =
        "colliders[1].dynamic: needs exactly one of \"density\" [kg/m^3] and \"mass\" [kg]";
    expectError(withDynamic(R"("density": 500, "mass": 2)"), ErrorCode::BadMetadata, {problem});
    expectError(withDynamic(""), ErrorCode::BadMetadata, {problem});
    expectError(withDynamic(R"("linearVelocity": [1, 0, 0], "friction": 0.2)"),
                ErrorCode::BadMetadata, {problem});
    // The structure is checked before the values: both given, both out of range.
    expectError(withDynamic(R"("density": 0, "mass": -1)"), ErrorCode::BadMetadata, {problem});
}

TEST(SceneReader, RejectsADynamicColliderThatAlsoHasMotion) {
    const std::string problem =
        "colliders[1].dynamic: not allowed with \"motion\": a collider is moved by the fluid "
        "(dynamic) or by its motion (kinematic), not both";
    expectError(withDynamic(R"("density": 500)", R"(, "motion": {"linearVelocity": [1, 0, 0]})"),
                ErrorCode::BadMetadata, {problem});
    expectError(withDynamic(R"("mass": 2)", R"(, "motion": {"keyframes": [
                    {"time": 0, "translation": [0, 0, 0]}]})"),
                ErrorCode::BadMetadata, {problem});
    // Even a motion that moves nothing: the file says two things about one collider.
    expectError(withDynamic(R"("mass": 2)", R"(, "motion": {})"), ErrorCode::BadMetadata,
                {problem});
}

TEST(SceneReader, RejectsAnUnknownKeyInsideDynamicSuggestingTheClosest) {
    expectError(withDynamic(R"("densty": 500)"), ErrorCode::BadMetadata,
                {"colliders[1].dynamic.densty: unknown key \"densty\" (did you mean "
                 "\"density\"?)"});
    expectError(withDynamic(R"("mass": 1, "restitusion": 0.5)"), ErrorCode::BadMetadata,
                {"colliders[1].dynamic.restitusion", "did you mean \"restitution\"?"});
    expectError(withDynamic(R"("mass": 1, "angularVelocty": [0, 0, 0])"), ErrorCode::BadMetadata,
                {"colliders[1].dynamic.angularVelocty", "did you mean \"angularVelocity\"?"});
    // Nothing close: the known keys are listed. Kinematic keys do not belong inside "dynamic".
    expectError(withDynamic(R"("mass": 1, "keyframes": [])"), ErrorCode::BadMetadata,
                {"colliders[1].dynamic.keyframes: unknown key \"keyframes\" (known keys: density "
                 "mass linearVelocity angularVelocity friction restitution)"});
    // A misspelt "dynamic" on the collider is caught one level up.
    expectError(withCollider(R"("asset": "b.slc", "dynamc": {"mass": 1})"), ErrorCode::BadMetadata,
                {"colliders[1].dynamc: unknown key \"dynamc\" (did you mean \"dynamic\"?)"});
}

TEST(SceneReader, RejectsWrongTypesInsideDynamicNamingTheExpectedType) {
    struct Case {
        std::string json;
        std::string part;
    };
    const std::vector<Case> cases = {
        {withDynamic(R"("mass": 1, "linearVelocity": [1, 0])"),
         "colliders[1].dynamic.linearVelocity: expected an array of 3 numbers [x, y, z], got an "
         "array of 2 elements"},
        {withDynamic(R"("mass": 1, "angularVelocity": [0, 90, 0, 0])"),
         "colliders[1].dynamic.angularVelocity: expected an array of 3 numbers [x, y, z], got an "
         "array of 4 elements"},
        {withDynamic(R"("mass": 1, "linearVelocity": 3)"),
         "colliders[1].dynamic.linearVelocity: expected an array of 3 numbers [x, y, z], got the "
         "number 3"},
        {withDynamic(R"("density": "500")"),
         "colliders[1].dynamic.density: expected a number, got a string"},
        {withCollider(R"("asset": "b.slc", "dynamic": true)"),
         "colliders[1].dynamic: expected an object, got true"},
        {withCollider(R"("asset": "b.slc", "dynamic": [500])"),
         "colliders[1].dynamic: expected an object, got an array of 1 element"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.json);
        expectError(c.json, ErrorCode::BadMetadata, {c.part});
    }
}

// ---------------------------------------------------------------------------------------------
// Errors

TEST(SceneReader, RejectsUnknownKeyWithItsPath) {
    const auto r = parseScene(withCollider(R"("asset": "b.slc", "friction": 1.5)"), "scene.json",
                              kNoAssetCheck);
    ASSERT_FALSE(r.ok());
    // The example from the design: the exact message.
    EXPECT_EQ(r.error().detail, "scene.json: colliders[1].friction: 1.5 is out of range [0, 1]");
    EXPECT_EQ(r.error().code, ErrorCode::InvalidArgument);

    expectError(withSimulation(R"("kernelRadus": 0.04)"), ErrorCode::BadMetadata,
                {"simulation.kernelRadus", "unknown key \"kernelRadus\"",
                 "did you mean \"kernelRadius\"?"});
    expectError(R"({"colider": [], "fluid": []})", ErrorCode::BadMetadata,
                {": colider: unknown key", "did you mean \"colliders\"?"});
    expectError(withCollider(R"("asset": "b.slc", "motion": {"keyframes": [{"time": 0,
                "translation": [0, 0, 0], "rotaton": [0, 0, 0]}]})"),
                ErrorCode::BadMetadata,
                {"colliders[1].motion.keyframes[0].rotaton", "did you mean \"rotation\"?"});
}

TEST(SceneReader, ListsTheKnownKeysWhenNoneIsClose) {
    expectError(
        withSimulation(R"("viscosity": 0.1)"), ErrorCode::BadMetadata,
        {"simulation.viscosity: unknown key \"viscosity\" (known keys: spacing", "capacity boundary)"});
    // Hostile keys are shown escaped and cut short.
    expectError("{\"a\\u0001" + std::string(200, 'x') + "\": 1}", ErrorCode::BadMetadata,
                {": a\\x01xxx", "...: unknown key"});
}

TEST(SceneReader, RejectsDuplicateKeys) {
    expectError(withSimulation(R"("spacing": 0.02, "spacing": 0.03)"), ErrorCode::BadMetadata,
                {"simulation.spacing: duplicate key \"spacing\""});
}

TEST(SceneReader, RejectsWrongTypesNamingTheExpectedType) {
    struct Case {
        std::string json;
        std::vector<std::string> parts;
    };
    const std::vector<Case> cases = {
        {"[]", {"(top level): expected an object, got an array of 0 elements"}},
        {withSimulation(R"("spacing": "0.02")"),
         {"simulation.spacing: expected a number, got a string"}},
        {withSimulation(R"("gravity": [0, -9.81])"),
         {"simulation.gravity: expected an array of 3 numbers [x, y, z], got an array of 2"}},
        {withSimulation(R"("gravity": [0, null, 0])"),
         {"simulation.gravity[1]: expected a number, got null"}},
        {withSimulation(R"("substeps": 2.5)"),
         {"simulation.substeps: expected an integer, got 2.5"}},
        {withSimulation(R"("capacity": true)"),
         {"simulation.capacity: expected an integer, got true"}},
        {R"({"simulation": 3, "fluid": []})", {"simulation: expected an object, got the number 3"}},
        {R"({"fluid": {}})", {"fluid: expected an array, got an object"}},
        {R"({"fluid": [[]]})", {"fluid[0]: expected an object, got an array"}},
        {R"({"name": 7, "fluid": []})", {"name: expected a string, got the number 7"}},
        {R"({"description": ["x"], "fluid": []})", {"description: expected a string"}},
        {withCollider(R"("asset": 5)"), {"colliders[1].asset: expected a string"}},
        {withCollider(R"("asset": "")"), {"colliders[1].asset: expected a file path"}},
        {withCollider(R"("asset": "b.slc", "scale": [1, 1, 1])"),
         {"colliders[1].scale: expected a number, got an array of 3 elements"}},
        {withCollider(R"("asset": "b.slc", "motion": [])"),
         {"colliders[1].motion: expected an object"}},
        {withCollider(R"("asset": "b.slc", "motion": {"keyframes": {}})"),
         {"colliders[1].motion.keyframes: expected an array"}},
        {withEmitter({{"stop", "\"never\""}}), {"emitters[0].stop: expected a number"}},
        {R"({"version": "1", "fluid": []})", {"version: expected a number"}},
        {R"({"version": 1.5, "fluid": []})", {"version: expected an integer, got 1.5"}},
        {kMinimal.substr(0, kMinimal.size() - 1) +
             R"(, "camera": {"position": 1, "target": [0, 0, 0]}})",
         {"camera.position: expected an array of 3 numbers"}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.json);
        expectError(c.json, ErrorCode::BadMetadata, c.parts);
    }
}

TEST(SceneReader, RejectsMissingRequiredKeys) {
    const std::string scene = kMinimal.substr(0, kMinimal.size() - 1);
    struct Case {
        std::string json;
        std::string part;
    };
    const std::vector<Case> cases = {
        {R"({"fluid": [{"box": {"min": [0, 0, 0]}}]})",
         "fluid[0].box: missing required key \"max\""},
        {R"({"fluid": [{"sphere": {"radius": 1}}]})",
         "fluid[0].sphere: missing required key \"center\""},
        {R"({"fluid": [{"velocity": [0, 0, 0]}]})",
         "fluid[0]: missing required key \"box\" or \"sphere\""},
        {R"({"emitters": [{"position": [0, 0, 0], "direction": [0, -1, 0], "radius": 0.1}]})",
         "emitters[0]: missing required key \"speed\""},
        {R"({"emitters": [{"position": [0, 0, 0], "radius": 0.1, "speed": 1}]})",
         "emitters[0]: missing required key \"direction\""},
        {scene + R"(, "colliders": [{"scale": 1}]})",
         "colliders[0]: missing required key \"asset\""},
        {scene + R"(, "colliders": [{"asset": "a.slc", "motion": {"keyframes": [{"time": 0}]}}]})",
         "colliders[0].motion.keyframes[0]: missing required key \"translation\""},
        {scene + R"(, "domain": {"max": [1, 1, 1]}})", "domain: missing required key \"min\""},
        {scene + R"(, "camera": {"position": [1, 1, 1]}})",
         "camera: missing required key \"target\""},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.json);
        expectError(c.json, ErrorCode::BadMetadata, {c.part});
    }
}

TEST(SceneReader, RejectsStructuralMistakes) {
    const std::string scene = kMinimal.substr(0, kMinimal.size() - 1);
    expectError(R"({"fluid": [], "emitters": []})", ErrorCode::BadMetadata,
                {"fluid: a scene needs at least one fluid block"});
    expectError(R"({"name": "empty"})", ErrorCode::BadMetadata,
                {"fluid: a scene needs at least one fluid block"});
    expectError(R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [1, 1, 1]},
                               "sphere": {"center": [0, 0, 0], "radius": 1}}]})",
                ErrorCode::BadMetadata, {"fluid[0]: has both \"box\" and \"sphere\""});
    expectError(scene + R"(, "colliders": [{"asset": "a.slc", "motion": {"keyframes": []}}]})",
                ErrorCode::BadMetadata, {"colliders[0].motion.keyframes: needs at least 1 key"});
    expectError(scene + R"(, "colliders": [{"asset": "a.slc", "motion": {
                    "linearVelocity": [1, 0, 0],
                    "keyframes": [{"time": 0, "translation": [0, 0, 0]}]}}]})",
                ErrorCode::BadMetadata,
                {"colliders[0].motion: has both \"keyframes\" and velocities"});
    expectError(scene + R"(, "colliders": [{"asset": "a.slc", "rotation": [0, 90, 0], "motion": {
                    "keyframes": [{"time": 0, "translation": [0, 0, 0]}]}}]})",
                ErrorCode::BadMetadata,
                {"colliders[0].rotation: not allowed with motion.keyframes"});
    std::string many = scene + R"(, "colliders": [)";
    for (int i = 0; i <= int(kMaxSceneColliders); ++i)
        many += std::string(i ? ", " : "") + R"({"asset": "a.slc"})";
    expectError(many + "]}", ErrorCode::InvalidArgument,
                {"colliders: 65 colliders, more than the limit 64"});
}

TEST(SceneReader, RejectsOutOfRangeValuesNamingTheRange) {
    const std::string scene = kMinimal.substr(0, kMinimal.size() - 1);
    struct Case {
        std::string json;
        std::string part;
    };
    const std::vector<Case> cases = {
        {withSimulation(R"("spacing": 0)"), "simulation.spacing: 0 is out of range [0.0001, 10]"},
        {withSimulation(R"("spacing": 11)"), "simulation.spacing: 11 is out of range [0.0001, 10]"},
        {withSimulation(R"("kernelRadius": 0.01)"),
         "simulation.kernelRadius: 0.01 is out of range [0.03, 0.08] (1.5 to 4 times spacing 0.02)"},
        {withSimulation(R"("kernelRadius": 0.0801)"),
         "simulation.kernelRadius: 0.0801 is out of range"},
        {withSimulation(R"("restDensity": 0)"),
         "simulation.restDensity: 0 is out of range: must be > 0"},
        {withSimulation(R"("timeStep": 0)"), "simulation.timeStep: 0 is out of range (0, 1]"},
        {withSimulation(R"("timeStep": 1.5)"), "simulation.timeStep: 1.5 is out of range (0, 1]"},
        {withSimulation(R"("substeps": 0)"), "simulation.substeps: 0 is out of range [1, 1000]"},
        {withSimulation(R"("substeps": 1001)"),
         "simulation.substeps: 1001 is out of range [1, 1000]"},
        {withSimulation(R"("substeps": -3)"), "simulation.substeps: -3 is out of range [1, 1000]"},
        {withSimulation(R"("minIterations": 0)"),
         "simulation.minIterations: 0 is out of range [1, 1000]"},
        {withSimulation(R"("maxIterations": 5000)"),
         "simulation.maxIterations: 5000 is out of range"},
        {withSimulation(R"("minIterations": 10)"),
         "simulation.maxIterations: 8 (the default) is less than minIterations 10"},
        {withSimulation(R"("minIterations": 4, "maxIterations": 3)"),
         "simulation.maxIterations: 3 is less than minIterations 4"},
        {withSimulation(R"("targetDensityError": 1.5)"),
         "simulation.targetDensityError: 1.5 is out of range [0, 1]"},
        {withSimulation(R"("relaxation": -0.1)"),
         "simulation.relaxation: -0.1 is out of range [0, 100]"},
        {withSimulation(R"("scorrK": -1)"), "simulation.scorrK: -1 is out of range: must be >= 0"},
        {withSimulation(R"("scorrN": 9)"), "simulation.scorrN: 9 is out of range [1, 8]"},
        {withSimulation(R"("scorrDeltaQ": 0.04)"), "simulation.scorrDeltaQ: 0.04 is out of range "
                                                   "[0, 0.04) (0 to kernelRadius 0.04, excluded)"},
        {withSimulation(R"("xsph": 2)"), "simulation.xsph: 2 is out of range [0, 1]"},
        {withSimulation(R"("vorticity": -0.5)"),
         "simulation.vorticity: -0.5 is out of range: must be >= 0"},
        {withSimulation(R"("capacity": 0)"),
         "simulation.capacity: 0 is out of range [1, 16777216]"},
        {withSimulation(R"("capacity": 16777217)"),
         "simulation.capacity: 16777217 is out of range [1, 16777216]"},
        {withSimulation(R"("capacity": 18446744073709551615)"),
         "simulation.capacity: 1.8446744073709552e+19 is out of range [1, 16777216]"},
        {withSimulation(R"("substeps": 1e30)"),
         "simulation.substeps: 1e+30 is out of range [1, 1000]"},
        {R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [1, 0, 1]}}]})",
         "fluid[0].box.max: [1, 0, 1] must exceed min [0, 0, 0] on every axis (y: 0 <= 0)"},
        {R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [1, 0.01, 1]}}]})",
         "fluid[0].box: holds no particles at spacing 0.02 (every side must be at least one "
         "spacing long)"},
        {R"({"fluid": [{"sphere": {"center": [0, 0, 0], "radius": 0}}]})",
         "fluid[0].sphere.radius: 0 is out of range: must be > 0"},
        {R"({"fluid": [{"sphere": {"center": [0, 0, 0], "radius": 0.005}}]})",
         "fluid[0].sphere: holds no particles at spacing 0.02 (the radius must be at least spacing "
         "/ 2)"},
        {withEmitter({{"direction", "[0, 0, 0]"}}),
         "emitters[0].direction: [0, 0, 0] has no direction (zero vector)"},
        {withEmitter({{"radius", "0.009"}}),
         "emitters[0].radius: 0.009 is out of range: must be >= 0.01 (at least spacing / 2)"},
        {withEmitter({{"speed", "0"}}), "emitters[0].speed: 0 is out of range: must be > 0"},
        {withEmitter({{"rate", "-1"}}), "emitters[0].rate: -1 is out of range: must be >= 0"},
        {withEmitter({{"start", "-1"}}), "emitters[0].start: -1 is out of range: must be >= 0"},
        {withEmitter({{"start", "2"}, {"stop", "2"}}),
         "emitters[0].stop: 2 is out of range: must be > 2 (after start 2)"},
        {withCollider(R"("asset": "b.slc", "friction": -0.1)"),
         "colliders[1].friction: -0.1 is out of range [0, 1]"},
        {withCollider(R"("asset": "b.slc", "scale": 0)"),
         "colliders[1].scale: 0 is out of range: must be > 0"},
        {withCollider(R"("asset": "b.slc", "motion": {"keyframes": [
             {"time": 1, "translation": [0, 0, 0]}, {"time": 1, "translation": [1, 0, 0]}]})"),
         "colliders[1].motion.keyframes[1].time: 1 is not after the previous key's time 1 (times "
         "must strictly increase)"},
        {scene + R"(, "domain": {"min": [0, 0, 0], "max": [1, 1, 0.01]}})",
         "domain.max: the domain is 0.01 wide on z, less than one spacing 0.02"},
        {scene + R"(, "camera": {"position": [1, 1, 1], "target": [0, 0, 0], "fov": 179}})",
         "camera.fov: 179 is out of range (1, 179)"},
        {scene + R"(, "camera": {"position": [1, 1, 1], "target": [1, 1, 1]}})",
         "camera.target: [1, 1, 1] equals the position"},
        {R"({"version": 0, "fluid": []})", "version: 0 is out of range [1, 1]"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.json);
        expectError(c.json, ErrorCode::InvalidArgument, {c.part});
    }
}

TEST(SceneReader, RejectsACapacitySmallerThanTheBlocksNamingBothNumbers) {
    expectError(
        withSimulation(R"("capacity": 100)"), ErrorCode::InvalidArgument,
        {"simulation.capacity: 100 is smaller than the 125 particles the fluid blocks hold"});
}

TEST(SceneReader, RejectsScenesNeedingMoreParticlesThanTheLimit) {
    // 1 m^3 at 2 mm: 500^3 particles.
    expectError(R"({"simulation": {"spacing": 0.002},
                    "fluid": [{"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}]})",
                ErrorCode::SizeOverflow,
                {"fluid[0].box: holds more than 16777216 particles (the limit) at spacing 0.002"});
    // Two blocks of 250^3 particles: under the limit each, over it together.
    const std::string big = R"({"box": {"min": [0, 0, 0], "max": [5, 5, 5]}})";
    expectError(R"({"fluid": [)" + big + ", " + big + "]}", ErrorCode::SizeOverflow,
                {"fluid: the fluid blocks hold 31250000 particles, more than the limit 16777216"});
    // An emitter running for a long time with no explicit capacity ...
    expectError(withEmitter({{"stop", "1e6"}}), ErrorCode::SizeOverflow,
                {"simulation.capacity: the scene needs 650000000 particles (0 in fluid blocks + "
                 "650000000 from emitters), more than the limit 16777216",
                 "set capacity"});
    // ... is fine with one.
    const std::string capped = withEmitter({{"stop", "1e6"}});
    EXPECT_EQ(
        parseOk(R"({"simulation": {"capacity": 5000}, )" + capped.substr(1)).simulation.capacity,
        5000u);
    expectError(withEmitter({{"radius", "100"}}), ErrorCode::SizeOverflow,
                {"emitters[0].radius: a disc of radius 100 holds more than 16777216"});
}

TEST(SceneReader, RejectsANewerVersion) {
    expectError(R"({"version": 2, "fluid": []})", ErrorCode::UnsupportedVersion,
                {"version: version 2 is newer than this build reads (1)"});
    // Checked before the keys: a newer file may use keys this build has never heard of.
    expectError(R"({"version": 3, "hologram": true})", ErrorCode::UnsupportedVersion,
                {"version: version 3 is newer"});
    EXPECT_TRUE(parseScene(R"({"version": 1, )" + kMinimal.substr(1), "scene.json").ok());
}

TEST(SceneReader, RejectsNonFiniteAndHugeNumbersNamingThePath) {
    expectError(withSimulation(R"("spacing": NaN)"), ErrorCode::NonFinite,
                {"simulation.spacing: NaN is not a finite number"});
    expectError(withSimulation(R"("gravity": [0, -Infinity, 0])"), ErrorCode::NonFinite,
                {"simulation.gravity[1]: -Infinity is not a finite number"});
    expectError(withCollider(R"("asset": "b.slc", "friction": Inf)"), ErrorCode::NonFinite,
                {"colliders[1].friction: Infinity is not a finite number"});
    expectError(withSimulation(R"("scorrK": 1e300)"), ErrorCode::NonFinite,
                {"simulation.scorrK: 1e+300 is not finite as a 32-bit float"});
    expectError(withSimulation(R"("gravity": [0, -1e39, 0])"), ErrorCode::NonFinite,
                {"simulation.gravity[1]: -1e+39 is not finite as a 32-bit float"});
    // Beyond the double range the parser itself stops; the message still says where.
    expectError("{\"fluid\": [],\n \"simulation\": {\"spacing\": 1e400}}", ErrorCode::NonFinite,
                {"scene.json:2:28: simulation.spacing: JSON syntax error: number too big"});
    expectError(withSimulation(R"("timeStep": 2e308)"), ErrorCode::NonFinite,
                {"simulation.timeStep: Infinity is not a finite number"});
    // rapidjson's full-precision mode read this one as -3.8e-288; the reader must not.
    expectError(withSimulation(R"("timeStep": 123456789012345678901234567890e300)"),
                ErrorCode::NonFinite, {"simulation.timeStep: Infinity is not a finite number"});
    // ... and this one (Tencent/rapidjson#2326) as 3.7e-40.
    EXPECT_FLOAT_EQ(parseOk(withSimulation(R"("xsph": 0.184467440737095516159)")).simulation.xsph,
                    0.18446744f);
    // A number too small for a float is read as 0 and then range-checked like any other.
    expectError(withSimulation(R"("spacing": 1e-400)"), ErrorCode::InvalidArgument,
                {"simulation.spacing: 0 is out of range"});
}

TEST(SceneReader, RejectsSyntaxErrorsWithLineAndColumn) {
    expectError("{\n  \"simulation\": {\"spacing\": 0.02,,}\n}", ErrorCode::BadMetadata,
                {"scene.json:2:", "simulation.spacing: JSON syntax error: missing a key"});
    expectError("{\"fluid\": [1 2]}", ErrorCode::BadMetadata,
                {"scene.json:1:14: fluid[1]: JSON syntax error: missing ',' or ']'"});
    expectError("", ErrorCode::BadMetadata, {"scene.json:1:1: (top level): JSON syntax error"});
    expectError(kMinimal + " {}", ErrorCode::BadMetadata, {"text after the end of the top-level"});
    expectError(withSimulation("\"spacing\": 0.02 // comment\n"), ErrorCode::BadMetadata,
                {"JSON syntax error"});
    expectError(withSimulation(R"("spacing": 0.02,)"), ErrorCode::BadMetadata,
                {"simulation.spacing: JSON syntax error"}); // trailing commas are not JSON
    expectError("{\"name\": \"\xC3\x28\"}", ErrorCode::BadMetadata,
                {"name: JSON syntax error: invalid UTF-8"});
    std::string withNul = "{\"name\": \"a";
    withNul += '\0';
    withNul += "b\"}";
    expectError(withNul, ErrorCode::BadMetadata, {"name: JSON syntax error"});
}

TEST(SceneReader, RejectsDeepNestingWithoutRecursing) {
    const std::string deep =
        "{\"fluid\": " + std::string(1'000'000, '[') + std::string(1'000'000, ']') + "}";
    expectError(deep, ErrorCode::BadMetadata, {"fluid[0][0][0]", "nested deeper than 32 levels"});
}

TEST(SceneReader, RejectsEveryTruncatedPrefixOfAValidScene) {
    const std::string text = readText(kAssetsDir / "funnel.json");
    ASSERT_TRUE(parseScene(text, "funnel.json", kNoAssetCheck).ok());
    const std::size_t end = text.rfind('}');
    ASSERT_NE(end, std::string::npos);
    for (std::size_t len = 0; len <= end; ++len) {
        const auto r =
            parseScene(std::string_view(text).substr(0, len), "funnel.json", kNoAssetCheck);
        ASSERT_FALSE(r.ok()) << "prefix of " << len << " bytes accepted";
        EXPECT_EQ(r.error().code, ErrorCode::BadMetadata) << r.error().message();
        EXPECT_EQ(r.error().detail.rfind("funnel.json:", 0), 0u) << r.error().detail;
    }
}

TEST(SceneReader, SurvivesRandomCorruptionOfAValidScene) {
    const std::string text = readText(kAssetsDir / "wave-sphere.json");
    std::mt19937 rng(20240611);
    const std::string alphabet = "{}[]:,\".-+eE0123456789 \nNaInfty\\u\x80\xff";
    int rejected = 0;
    for (int i = 0; i < 3000; ++i) {
        std::string t = text;
        const int edits = 1 + int(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const std::size_t at = rng() % t.size();
            switch (rng() % 3) {
            case 0:
                t[at] = alphabet[rng() % alphabet.size()];
                break;
            case 1:
                t.erase(at, 1 + rng() % 8);
                break;
            default:
                t.insert(at, 1, alphabet[rng() % alphabet.size()]);
                break;
            }
        }
        const auto r = parseScene(t, "fuzz.json", kNoAssetCheck);
        if (!r.ok()) {
            ++rejected;
            EXPECT_EQ(r.error().detail.rfind("fuzz.json", 0), 0u) << r.error().detail;
        }
    }
    EXPECT_GT(rejected, 1000); // the edits do break most files
}

TEST(SceneReader, RejectsFilesItCannotReadOrThatAreTooLarge) {
    BuildTempDir dir;
    const auto missing = readScene(dir.path() / "missing.json");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::Io);
    EXPECT_NE(missing.error().detail.find("missing.json: cannot read the scene file"),
              std::string::npos);

    const auto folder = readScene(dir.path());
    ASSERT_FALSE(folder.ok());
    EXPECT_EQ(folder.error().code, ErrorCode::Io);
    EXPECT_NE(folder.error().detail.find("not a regular file"), std::string::npos);

    std::string huge(std::size_t(kMaxSceneFileBytes) + 1, ' ');
    const auto big = parseScene(huge, "big.json");
    ASSERT_FALSE(big.ok());
    EXPECT_EQ(big.error().code, ErrorCode::SizeOverflow);
    EXPECT_NE(big.error().detail.find("big.json: 16777217 bytes, more than the scene-file limit"),
              std::string::npos)
        << big.error().detail;
    const fs::path bigFile = dir.write("big.json", huge);
    const auto bigRead = readScene(bigFile);
    ASSERT_FALSE(bigRead.ok());
    EXPECT_EQ(bigRead.error().code, ErrorCode::SizeOverflow);

    // Just under the limit, padding is fine.
    const fs::path padded = dir.write("padded.json", kMinimal + std::string(1 << 20, '\n'));
    EXPECT_TRUE(readScene(padded).ok());
}

} // namespace
} // namespace sluice::test
