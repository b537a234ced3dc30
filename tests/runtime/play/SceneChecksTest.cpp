// Scene sanity checks on the CPU: the shipped scenes pass, and each kind of likely mistake is
// reported with where it is and how many particles it concerns.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ShippedScenes.h"
#include "play/SceneChecks.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

namespace fs = std::filesystem;

const fs::path kAssets = SLUICE_BUILD_ASSETS_DIR; // scenes and baked colliders, side by side

struct Checked {
    format::Scene scene;
    std::vector<PlayWarning> warnings;
};

/// The warnings of a scene written inline; its colliders are named relative to the assets.
Checked check(const std::string& json) {
    auto scene = format::parseScene(json, kAssets / "checks.json");
    EXPECT_TRUE(scene) << scene.error().message();
    if (!scene)
        return {};
    auto colliders = loadSceneColliders(*scene);
    EXPECT_TRUE(colliders) << colliders.error().message();
    if (!colliders)
        return {};
    std::vector<PlayWarning> warnings = checkScene(*scene, *colliders);
    return {std::move(*scene), std::move(warnings)};
}

std::vector<PlayWarning> ofKind(const std::vector<PlayWarning>& warnings, const std::string& kind) {
    std::vector<PlayWarning> out;
    std::copy_if(warnings.begin(), warnings.end(), std::back_inserter(out),
                 [&](const PlayWarning& w) { return w.kind == kind; });
    return out;
}

std::string all(const std::vector<PlayWarning>& warnings) {
    std::string text;
    for (const PlayWarning& w : warnings)
        text += warningLine(w) + "\n";
    return text;
}

class ShippedSceneChecks : public ::testing::TestWithParam<const char*> {};

TEST_P(ShippedSceneChecks, GiveNoWarnings) {
    auto scene = format::readScene(kAssets / GetParam());
    ASSERT_TRUE(scene) << scene.error().message();
    auto colliders = loadSceneColliders(*scene);
    ASSERT_TRUE(colliders) << colliders.error().message();
    const std::vector<PlayWarning> warnings = checkScene(*scene, *colliders);
    EXPECT_TRUE(warnings.empty()) << all(warnings);
}

INSTANTIATE_TEST_SUITE_P(Assets, ShippedSceneChecks, test::shippedScenes(),
                         test::ShippedSceneName{});

TEST(SceneChecks, ReportsABallOutsideTheDomainWithItsParticleCount) {
    const Checked c = check(R"({"fluid": [
        {"box": {"min": [0.1, 0.1, 0.1], "max": [0.2, 0.2, 0.2]}},
        {"sphere": {"center": [5, 5, 5], "radius": 0.05}}],
        "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}})");
    const auto outside = ofKind(c.warnings, "outside-domain");
    ASSERT_EQ(outside.size(), 1u) << all(c.warnings);
    format::Scene ball = c.scene;
    ball.blocks.erase(ball.blocks.begin());
    const std::size_t particles = fillBlocks(ball).size();
    ASSERT_GT(particles, 0u);
    const std::string& text = outside[0].text;
    EXPECT_NE(text.find("checks.json: fluid[1]: "), std::string::npos) << text;
    EXPECT_NE(text.find(std::to_string(particles) + " of " + std::to_string(particles) +
                        " particles start outside the domain box"),
              std::string::npos)
        << text;
}

TEST(SceneChecks, CountsOnlyTheParticlesOfABlockThatCrossTheDomainWall) {
    // 5 x 5 x 5 particles at 2 cm; the domain's x wall cuts the last layer of 25 off.
    const Checked c = check(R"({"simulation": {"spacing": 0.02}, "fluid": [
        {"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
        "domain": {"min": [0, 0, 0], "max": [0.09, 1, 1]}})");
    const auto outside = ofKind(c.warnings, "outside-domain");
    ASSERT_EQ(outside.size(), 1u) << all(c.warnings);
    EXPECT_NE(outside[0].text.find("25 of 125 particles"), std::string::npos) << outside[0].text;
}

TEST(SceneChecks, AcceptsABlockFillingTheDomainExactly) {
    const Checked c = check(R"({"simulation": {"spacing": 0.02}, "fluid": [
        {"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
        "domain": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}})");
    EXPECT_TRUE(c.warnings.empty()) << all(c.warnings);
}

TEST(SceneChecks, ReportsAnEmitterOutsideTheDomain) {
    const Checked c = check(R"({"emitters": [{"position": [0.5, 2, 0.5], "direction": [0, -1, 0],
        "radius": 0.04,
        "speed": 1}], "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}})");
    const auto outside = ofKind(c.warnings, "outside-domain");
    ASSERT_EQ(outside.size(), 1u) << all(c.warnings);
    EXPECT_NE(outside[0].text.find("emitters[0]"), std::string::npos) << outside[0].text;
}

TEST(SceneChecks, CountsFluidSpawnedInsideOrAgainstACollider) {
    // sphere.slc is a ball of radius 0.25 m; scaled by 0.4 it is 0.1 m, centred at the origin.
    // The block's particle centres lie on the 2 cm lattice offset by 1 cm.
    const Checked c = check(R"({"simulation": {"spacing": 0.02}, "fluid": [
        {"box": {"min": [-0.2, -0.2, -0.2], "max": [0.2, 0.2, 0.2]}}],
        "colliders": [{"asset": "sphere.slc", "scale": 0.4}]})");
    const auto near = ofKind(c.warnings, "fluid-in-collider");
    ASSERT_EQ(near.size(), 1u) << all(c.warnings);
    // Independently: particles whose centre is within the ball's radius plus a particle radius
    // (0.11 m), give or take the tessellation and a voxel of interpolation (5 mm).
    std::size_t lower = 0, upper = 0;
    for (const ParticleState& p : fillBlocks(c.scene)) {
        const float d = glm::length(p.position);
        lower += d < 0.105f ? 1 : 0;
        upper += d < 0.115f ? 1 : 0;
    }
    const std::string& text = near[0].text;
    const std::size_t at = text.find(": ", text.find("fluid[0]")) + 2;
    const std::size_t count = std::stoul(text.substr(at));
    EXPECT_GE(count, lower) << text;
    EXPECT_LE(count, upper) << text;
    EXPECT_NE(text.find("colliders[0] (sphere.slc)"), std::string::npos) << text;
}

TEST(SceneChecks, PosesTheColliderAsTheSceneDoes) {
    // The same block and ball, the ball moved 1 m away: no overlap.
    const Checked c = check(R"({"simulation": {"spacing": 0.02}, "fluid": [
        {"box": {"min": [-0.2, -0.2, -0.2], "max": [0.2, 0.2, 0.2]}}],
        "colliders": [{"asset": "sphere.slc", "scale": 0.4, "translation": [1, 0, 0]}]})");
    EXPECT_TRUE(c.warnings.empty()) << all(c.warnings);
}

TEST(SceneChecks, ReportsAColliderInCentimetresWithTheScaleHint) {
    // The 0.5 m ball scaled by 100, as a mesh modelled in centimetres comes out: 50 m.
    const Checked c = check(R"({"simulation": {"spacing": 0.02}, "fluid": [
        {"box": {"min": [60, 0, 0], "max": [60.1, 0.1, 0.1]}}],
        "colliders": [{"asset": "sphere.slc", "scale": 100}]})");
    const auto scale = ofKind(c.warnings, "collider-scale");
    ASSERT_EQ(scale.size(), 1u) << all(c.warnings);
    EXPECT_NE(scale[0].text.find("colliders[0] (sphere.slc)"), std::string::npos) << scale[0].text;
    EXPECT_NE(scale[0].text.find("sluice-bake bake --scale"), std::string::npos) << scale[0].text;
}

TEST(SceneChecks, ReportsAColliderSmallerThanAParticle) {
    const Checked c = check(R"({"simulation": {"spacing": 0.02}, "fluid": [
        {"box": {"min": [1, 0, 0], "max": [1.1, 0.1, 0.1]}}],
        "colliders": [{"asset": "sphere.slc", "scale": 0.01}]})");
    const auto scale = ofKind(c.warnings, "collider-scale");
    ASSERT_EQ(scale.size(), 1u) << all(c.warnings);
    EXPECT_NE(scale[0].text.find("particles are larger than the collider"), std::string::npos)
        << scale[0].text;
}

TEST(SceneChecks, MeasuresAColliderAsPlacedInTheWorld) {
    auto scene = format::parseScene(R"({"fluid": [{"box": {"min": [1, 1, 1], "max": [1.1, 1.1,
        1.1]}}], "colliders": [{"asset": "sphere.slc", "scale": 0.4}]})",
                                    kAssets / "checks.json");
    ASSERT_TRUE(scene) << scene.error().message();
    auto colliders = loadSceneColliders(*scene);
    ASSERT_TRUE(colliders) << colliders.error().message();
    const glm::dvec3 size = colliderWorldSize(scene->colliders[0], (*colliders)[0]);
    const double voxel = (*colliders)[0].meta.voxelSize * 0.4;
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(size[a], 0.2, voxel) << "axis " << a;
    const auto lines = describeColliders(*scene, *colliders);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(lines[0].rfind("colliders[0] sphere.slc: 0.", 0), 0u) << lines[0];
    EXPECT_NE(lines[0].find(" m (scale 0.4)"), std::string::npos) << lines[0];
}

/// A scene of a small pool with crate.slc (0.12 m) as a dynamic body: `dynamic` its "dynamic"
/// object, `at` its translation.
std::string bodyScene(const std::string& dynamic, const std::string& at = "[0.5, 0.3, 0.5]") {
    return R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [1, 0.1, 1]}}],
        "colliders": [{"asset": "crate.slc", "translation": )" +
           at + R"(, "dynamic": )" + dynamic + R"(}],
        "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}})";
}

TEST(SceneChecks, ReportsBodiesLighterOrDenserThanRealMaterials) {
    EXPECT_TRUE(check(bodyScene(R"({"density": 500})")).warnings.empty());
    EXPECT_TRUE(check(bodyScene(R"({"density": 10})")).warnings.empty());
    EXPECT_TRUE(check(bodyScene(R"({"density": 25000})")).warnings.empty());
    for (const char* dynamic : {R"({"density": 1e-30})", R"({"density": 9})",
                                R"({"density": 30000})", R"({"mass": 0.001})"}) {
        const Checked c = check(bodyScene(dynamic));
        const auto density = ofKind(c.warnings, "body-density");
        ASSERT_EQ(density.size(), 1u) << dynamic << "\n" << all(c.warnings);
        EXPECT_EQ(c.warnings.size(), 1u) << all(c.warnings);
        EXPECT_NE(density[0].text.find("checks.json: colliders[0] (crate.slc): "),
                  std::string::npos)
            << density[0].text;
        EXPECT_NE(density[0].text.find("kg/m^3"), std::string::npos) << density[0].text;
    }
    // A mass of 1 g over the crate's 0.12^3 m^3: 0.579 kg/m^3, said to come from the mass.
    const auto grams = check(bodyScene(R"({"mass": 0.001})")).warnings;
    ASSERT_EQ(grams.size(), 1u);
    EXPECT_NE(grams[0].text.find("a dynamic body of 0.579 kg/m^3 (its mass over its volume)"),
              std::string::npos)
        << grams[0].text;
}

TEST(SceneChecks, ReportsABodyStartingOutsideOrAcrossTheDomain) {
    EXPECT_TRUE(check(bodyScene(R"({"density": 500})", "[0.5, 0.3, 0.5]")).warnings.empty());
    // Near a wall from inside is not across it: its surface is 0.01 m from x = 0.
    EXPECT_TRUE(check(bodyScene(R"({"density": 500})", "[0.07, 0.3, 0.5]")).warnings.empty());
    const Checked across = check(bodyScene(R"({"density": 500})", "[0.98, 0.3, 0.5]"));
    const auto partly = ofKind(across.warnings, "body-outside-domain");
    ASSERT_EQ(partly.size(), 1u) << all(across.warnings);
    EXPECT_NE(partly[0].text.find("colliders[0] (crate.slc): the dynamic body starts partly "
                                  "outside the domain box (0, 0, 0) to (1, 1, 1)"),
              std::string::npos)
        << partly[0].text;
    const Checked away = check(bodyScene(R"({"density": 500})", "[3, 0.3, 0.5]"));
    const auto outside = ofKind(away.warnings, "body-outside-domain");
    ASSERT_EQ(outside.size(), 1u) << all(away.warnings);
    EXPECT_NE(outside[0].text.find("the dynamic body starts outside the domain box"),
              std::string::npos)
        << outside[0].text;
}

TEST(SceneChecks, ReportsAFixedOddIterationCount) {
    // Fixed by a zero target or by minIterations = maxIterations; odd counts only.
    const std::string box = R"("fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}])";
    const std::string fixed3Json =
        R"({"simulation": {"targetDensityError": 0, "maxIterations": 3}, )" + box + "}";
    const Checked fixed3 = check(fixed3Json);
    const auto odd = ofKind(fixed3.warnings, "odd-iterations");
    ASSERT_EQ(odd.size(), 1u) << all(fixed3.warnings);
    EXPECT_NE(odd[0].text.find("checks.json: simulation: every substep runs 3 solver iterations"),
              std::string::npos)
        << odd[0].text;
    EXPECT_NE(odd[0].text.find("use 2 or 4"), std::string::npos) << odd[0].text;
    const Checked pinned5 =
        check(R"({"simulation": {"minIterations": 5, "maxIterations": 5}, )" + box + "}");
    EXPECT_EQ(ofKind(pinned5.warnings, "odd-iterations").size(), 1u) << all(pinned5.warnings);
    const Checked one =
        check(R"({"simulation": {"minIterations": 1, "maxIterations": 1}, )" + box + "}");
    ASSERT_EQ(ofKind(one.warnings, "odd-iterations").size(), 1u) << all(one.warnings);
    EXPECT_NE(one.warnings[0].text.find("1 solver iteration, an odd count"), std::string::npos)
        << one.warnings[0].text;
    EXPECT_NE(one.warnings[0].text.find("use 2,"), std::string::npos) << one.warnings[0].text;
    for (const char* quiet :
         {R"("targetDensityError": 0, "maxIterations": 4)", R"("maxIterations": 7)",
          R"("minIterations": 3, "maxIterations": 9)"}) {
        const Checked c = check(std::string(R"({"simulation": {)") + quiet + "}, " + box + "}");
        EXPECT_TRUE(ofKind(c.warnings, "odd-iterations").empty()) << quiet << "\n"
                                                                  << all(c.warnings);
    }
}

TEST(SceneChecks, WarningLinesEndWithTheirKind) {
    EXPECT_EQ(warningLine({"outside-domain", "a.json: fluid[0]: text"}),
              "sluice-play: warning: a.json: fluid[0]: text [outside-domain]");
}

} // namespace
} // namespace sluice::rt
