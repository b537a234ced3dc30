// The scene reader: dynamic colliders (bodies), their two forms and their checks.
#include <gtest/gtest.h>

#include "SceneReaderTestUtil.h"

namespace sluice::test {
namespace {

using namespace sluice::format;
using namespace scenetest;
namespace fs = std::filesystem;

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

} // namespace
} // namespace sluice::test
