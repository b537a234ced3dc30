// The scene reader: every kind of error it reports, each naming the file, the JSON path and the
// problem.
#include <gtest/gtest.h>

#include "SceneReaderTestUtil.h"

namespace sluice::test {
namespace {

using namespace sluice::format;
using namespace scenetest;
namespace fs = std::filesystem;

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
    expectError(withSimulation(R"("viscosity": 0.1)"), ErrorCode::BadMetadata,
                {"simulation.viscosity: unknown key \"viscosity\" (known keys: spacing",
                 "capacity boundary)"});
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

// One scene and the part of the message it must be refused with.
struct OutOfRange {
    std::string json;
    std::string part;
};

void expectOutOfRange(const std::vector<OutOfRange>& cases) {
    for (const OutOfRange& c : cases) {
        SCOPED_TRACE(c.json);
        expectError(c.json, ErrorCode::InvalidArgument, {c.part});
    }
}

TEST(SceneReader, RejectsOutOfRangeSimulationValuesNamingTheRange) {
    expectOutOfRange({
        {withSimulation(R"("spacing": 0)"), "simulation.spacing: 0 is out of range [0.0001, 10]"},
        {withSimulation(R"("spacing": 11)"), "simulation.spacing: 11 is out of range [0.0001, 10]"},
        {withSimulation(R"("kernelRadius": 0.01)"), "simulation.kernelRadius: 0.01 is out of range "
                                                    "[0.03, 0.08] (1.5 to 4 times spacing 0.02)"},
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
    });
}

TEST(SceneReader, RejectsOutOfRangeSceneValuesNamingTheRange) {
    const std::string scene = kMinimal.substr(0, kMinimal.size() - 1);
    expectOutOfRange({
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
    });
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
