// Runtime faults through sluice-play (and the GPU bake's memory limit through sluice-bake):
// hostile parameters, corrupt colliders, a capacity too small for the emitters, too many
// particles for the GPU, particles and bodies that go non-finite or are lost, and no OpenGL
// 4.5 context.
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ProgramRun.h"
#include "ReliabilityTest.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/gpu/Context.h"

namespace sluice::reliability {
namespace {

using testrun::runProgram;
using testrun::RunResult;
using testrun::shown;

const fs::path kAssets = SLUICE_BUILD_ASSETS_DIR; // baked colliders and the shipped scenes

RunResult play(const fs::path& dir, const std::vector<std::string>& args,
               const std::vector<std::string>& env = {}) {
    if (env.empty())
        return runProgram(SLUICE_PLAY_EXE, dir, args);
    std::vector<std::string> all = env;
    all.push_back(SLUICE_PLAY_EXE);
    all.insert(all.end(), args.begin(), args.end());
    return runProgram("/usr/bin/env", dir, all);
}

/// A scene of a small block with `simulation` as its simulation object and `extra` top-level
/// members (each "key": value, comma-separated, may be empty).
std::string sceneText(const std::string& simulation, const std::string& extra = "") {
    return R"({"simulation": )" + simulation +
           R"(, "fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}])" +
           (extra.empty() ? "" : ", " + extra) + "}";
}

/// Largest storage block this machine's GL offers [bytes] (0 without a context).
std::uint64_t maxSsboBytes() {
    static const std::uint64_t bytes = [] {
        auto context = gpu::Context::createHeadless();
        return context ? context->info().maxSsboBytes : std::uint64_t(0);
    }();
    return bytes;
}

// --- Parameters -----------------------------------------------------------------------------

struct BadParameter {
    const char* name;
    std::string scene;
    const char* path; ///< the JSON path the message must name
    const char* code; ///< the error code name the message must end with
};

void PrintTo(const BadParameter& bad, std::ostream* os) {
    *os << bad.name;
}

class HostileParameter : public ::testing::TestWithParam<BadParameter> {};

TEST_P(HostileParameter, ExitsTwoNamingThePathAndTheRule) {
    const BadParameter& bad = GetParam();
    const fs::path dir = freshDir(std::string("param-") + bad.name);
    writeText(dir / "scene.json", bad.scene);
    const RunResult run = play(dir, {(dir / "scene.json").string(), "--headless", "--steps", "1"});
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find("scene.json"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(bad.path), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(std::string("[") + bad.code + "]"), std::string::npos) << run.err;
}

INSTANTIATE_TEST_SUITE_P(
    Runtime, HostileParameter,
    ::testing::Values(
        BadParameter{"nanSpacing", sceneText(R"({"spacing": NaN})"), "simulation.spacing",
                     "NonFinite"},
        BadParameter{"infiniteTimeStep", sceneText(R"({"timeStep": Infinity})"),
                     "simulation.timeStep", "NonFinite"},
        BadParameter{"gravityBeyondFloat", sceneText(R"({"gravity": [0, -1e39, 0]})"),
                     "simulation.gravity", "NonFinite"},
        BadParameter{"negativeSpacing", sceneText(R"({"spacing": -0.02})"), "simulation.spacing",
                     "InvalidArgument"},
        BadParameter{"hugeSpacing", sceneText(R"({"spacing": 1e9})"), "simulation.spacing",
                     "InvalidArgument"},
        BadParameter{"zeroTimeStep", sceneText(R"({"timeStep": 0})"), "simulation.timeStep",
                     "InvalidArgument"},
        BadParameter{"zeroSubsteps", sceneText(R"({"substeps": 0})"), "simulation.substeps",
                     "InvalidArgument"},
        BadParameter{"tooManyIterations", sceneText(R"({"maxIterations": 100000})"),
                     "simulation.maxIterations", "InvalidArgument"},
        BadParameter{"negativeDensity", sceneText(R"({"restDensity": -1000})"),
                     "simulation.restDensity", "InvalidArgument"},
        BadParameter{"kernelBelowSpacing", sceneText(R"({"kernelRadius": 0.001})"),
                     "simulation.kernelRadius", "InvalidArgument"},
        BadParameter{"capacityOverTheLimit", sceneText(R"({"capacity": 4000000000})"),
                     "simulation.capacity", "InvalidArgument"},
        BadParameter{
            "blockOverTheLimit",
            R"({"simulation": {"spacing": 0.001}, "fluid": [{"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}]})",
            "fluid[0].box", "SizeOverflow"},
        BadParameter{
            "emitterForever",
            sceneText(
                "{}",
                R"("emitters": [{"position": [0, 1, 0], "direction": [0, -1, 0], "radius": 0.1, "speed": 1, "stop": 1e30}])"),
            "simulation.capacity", "SizeOverflow"},
        BadParameter{"tooManyColliders",
                     [] {
                         std::string colliders = R"("colliders": [)";
                         for (std::uint32_t i = 0; i <= format::kMaxSceneColliders; ++i)
                             colliders += std::string(i ? ", " : "") + R"({"asset": "a.slc"})";
                         return sceneText("{}", colliders + "]");
                     }(),
                     "colliders", "InvalidArgument"}),
    [](const auto& paramInfo) { return std::string(paramInfo.param.name); });

// --- Colliders ------------------------------------------------------------------------------

TEST(RuntimeFault, CorruptCollidersExitTwoNamingTheColliderTheFileAndTheError) {
    const fs::path dir = freshDir("corrupt-collider");
    const std::string good = readBytes(kAssets / "sphere.slc");
    ASSERT_GT(good.size(), 1000u) << "build sluice_assets first";
    struct Case {
        const char* file;
        std::string bytes;
        const char* code;
    };
    std::string flipped = good;
    flipped[good.size() / 2] ^= 0x10;
    std::string newer = good;
    newer[format::header_offset::kMajor] = 2;
    const std::vector<Case> cases = {
        {"half.slc", good.substr(0, good.size() / 2), "Truncated"},
        {"flipped.slc", flipped, "ChecksumMismatch"},
        {"newer.slc", newer, "UnsupportedVersion"},
        {"empty.slc", "", "Truncated"},
        {"text.slc", "this is not a collider", "Truncated"},
        {"mesh.slc", std::string("v 0 0 0\n") + std::string(100, 'x'), "BadMagic"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.file);
        writeText(dir / c.file, c.bytes);
        writeText(dir / "scene.json",
                  sceneText("{}", std::string(R"("colliders": [{"asset": ")") +
                                      (kAssets / "sphere.slc").string() + R"("}, {"asset": ")" +
                                      c.file + R"("}])"));
        const RunResult run =
            play(dir, {(dir / "scene.json").string(), "--headless", "--steps", "1"});
        EXPECT_EQ(run.code, 2) << shown(run);
        EXPECT_NE(run.err.find("scene.json"), std::string::npos) << run.err;
        EXPECT_NE(run.err.find("colliders[1]"), std::string::npos) << run.err;
        EXPECT_NE(run.err.find(c.file), std::string::npos) << run.err;
        EXPECT_NE(run.err.find(std::string("[") + c.code + "]"), std::string::npos) << run.err;
    }
    // A folder where the asset should be.
    fs::create_directories(dir / "folder.slc");
    writeText(dir / "scene.json", sceneText("{}", R"("colliders": [{"asset": "folder.slc"}])"));
    const RunResult run = play(dir, {(dir / "scene.json").string(), "--headless", "--steps", "1"});
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find("folder.slc"), std::string::npos) << run.err;
}

// --- Capacity and memory --------------------------------------------------------------------

TEST(RuntimeFault, ACapacityTooSmallForTheEmittersIsReportedOnceAndTheRunGoesOn) {
    const fs::path dir = freshDir("capacity");
    // A 13-particle disc every 0.02 s; 100 particles hold fewer than 8 layers.
    writeText(dir / "scene.json",
              R"({"simulation": {"spacing": 0.02, "capacity": 100},
                  "emitters": [{"position": [0, 0.5, 0], "direction": [0, -1, 0], "radius": 0.04,
                                "speed": 1}],
                  "domain": {"min": [-0.3, 0, -0.3], "max": [0.3, 0.6, 0.3]}})");
    const RunResult run =
        play(dir, {(dir / "scene.json").string(), "--headless", "--steps", "30", "--stats-every",
                   "1", "--stats-json", (dir / "stats.json").string(), "--check"});
    EXPECT_EQ(run.code, 0) << shown(run);
    const std::string what = "particle capacity 100 reached";
    const std::size_t at = run.err.find(what);
    ASSERT_NE(at, std::string::npos) << run.err;
    EXPECT_EQ(run.err.find(what, at + 1), std::string::npos) << "reported once: " << run.err;
    // "sluice-play: step N: particle capacity 100 reached; ..." on one line.
    const std::size_t line =
        run.err.rfind('\n', at) == std::string::npos ? 0 : run.err.rfind('\n', at) + 1;
    EXPECT_EQ(run.err.compare(line, 18, "sluice-play: step "), 0) << run.err;
    EXPECT_GE(std::atoi(run.err.c_str() + line + 18), 1) << run.err;
    const auto stats = nlohmann::json::parse(readBytes(dir / "stats.json"));
    EXPECT_EQ(stats["capacity"], 100);
    EXPECT_EQ(stats["steps"].back()["particles"], 100);
    bool flagged = false;
    for (const auto& step : stats["steps"])
        flagged = flagged || step.value("capacityReached", false);
    EXPECT_TRUE(flagged) << "the statistics record the step where emitters were held back";
}

TEST(RuntimeFault, MoreParticlesThanTheGpuCanHoldExitTwoNamingTheCapacity) {
    const std::uint64_t maxSsbo = maxSsboBytes();
    if (maxSsbo == 0)
        GTEST_SKIP() << "no GL context";
    // vec4 positions: 16 bytes a particle; the largest capacity a scene may ask for.
    const std::uint64_t needed = std::uint64_t(format::kMaxSceneParticles) * 16;
    if (needed <= maxSsbo)
        GTEST_SKIP() << "this GL's storage blocks (" << maxSsbo << " bytes) hold "
                     << format::kMaxSceneParticles << " particles";
    const fs::path dir = freshDir("gpu-capacity");
    writeText(dir / "scene.json",
              sceneText(R"({"capacity": )" + std::to_string(format::kMaxSceneParticles) + "}"));
    const RunResult run = play(dir, {(dir / "scene.json").string(), "--headless", "--steps", "1"});
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find("scene.json"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("simulation.capacity"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("[GpuOutOfMemory]"), std::string::npos) << run.err;
}

TEST(RuntimeFault, AGpuBakeTooLargeForTheGpuExitsTwoAndWritesNothing) {
    const std::uint64_t maxSsbo = maxSsboBytes();
    if (maxSsbo == 0)
        GTEST_SKIP() << "no GL context";
    // A grid one fifth larger than the largest storage buffer holds, within the grid limit.
    const double points = double(maxSsbo) / 4.0 * 1.2;
    if (points > double(format::kMaxAssetPoints))
        GTEST_SKIP() << "this GL's storage blocks hold the largest grid";
    const double perAxis = std::ceil(std::cbrt(points));
    const fs::path dir = freshDir("gpu-bake-too-large");
    writeText(dir / "tetra.obj",
              "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    writeText(dir / "out.slc", "previous");
    const RunResult run = runProgram(
        SLUICE_BAKE_EXE, dir,
        {"bake", (dir / "tetra.obj").string(), "-o", (dir / "out.slc").string(), "--backend", "gpu",
         "--padding", "0", "--voxel-size", std::to_string(1.0 / (perAxis - 1.0)), "--quiet"});
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find("tetra.obj"), std::string::npos) << run.err;
    EXPECT_EQ(readBytes(dir / "out.slc"), "previous");
    EXPECT_EQ(listDir(dir),
              (std::set<std::string>{"out.slc", "stderr.txt", "stdout.txt", "tetra.obj"}));
}

// --- Non-finite particles -------------------------------------------------------------------

TEST(RuntimeFault, ParticlesThatGoNonFiniteAreReportedWithTheirStepAndCheckFails) {
    // Gravity near the float limit and one-second steps: the velocity overflows to infinity on
    // the second step. Each particle that goes non-finite is reset to its last position and
    // counted; the run ends normally, and --check turns it into exit code 1.
    const fs::path dir = freshDir("non-finite");
    writeText(dir / "scene.json",
              sceneText(R"({"gravity": [0, -3e38, 0], "timeStep": 1, "substeps": 1})"));
    const std::vector<std::string> args = {(dir / "scene.json").string(),
                                           "--headless",
                                           "--steps",
                                           "6",
                                           "--stats-every",
                                           "1",
                                           "--stats-json",
                                           (dir / "stats.json").string()};
    RunResult run = play(dir, args);
    EXPECT_EQ(run.code, 0) << shown(run);
    EXPECT_NE(run.err.find("particles went non-finite"), std::string::npos) << run.err;
    const std::size_t at = run.err.find("sluice-play: step ");
    ASSERT_NE(at, std::string::npos) << run.err;
    const int step = std::atoi(run.err.c_str() + at + std::string("sluice-play: step ").size());
    EXPECT_GE(step, 1);
    const auto stats = nlohmann::json::parse(readBytes(dir / "stats.json"));
    std::uint64_t reported = 0;
    for (const auto& s : stats["steps"])
        reported += s["nonFinite"].get<std::uint64_t>();
    EXPECT_GT(reported, 0u);
    EXPECT_EQ(stats["steps"].back()["particles"], stats["steps"].front()["particles"])
        << "no particle is lost";
    for (const auto& s : stats["steps"]) // the reset keeps NaN out of the density solve
        EXPECT_TRUE(s["avgDensityError"].is_number() && !s["avgDensityError"].is_null()) << s;

    std::vector<std::string> checked = args;
    checked.push_back("--check");
    run = play(dir, checked);
    EXPECT_EQ(run.code, 1) << shown(run);
}

TEST(RuntimeFault, ABodyTheSolverLosesIsPutBackCountedAndFailsCheck) {
    // A crate of 1e-30 kg/m^3 in a shallow pool: the first push of the water throws it far
    // outside the domain (2.5e30 m before bodies were checked). It is put back at rest each
    // time and counted; the density warns before the run, and --check turns the loss into 1.
    const fs::path dir = freshDir("lost-body");
    const std::string crate = (kAssets / "crate.slc").string();
    writeText(dir / "scene.json",
              R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.3, 0.06, 0.3]}}],
                  "colliders": [{"asset": ")" +
                  crate + R"(", "translation": [0.15, 0.1, 0.15],
                                 "dynamic": {"density": 1e-30}}],
                  "domain": {"min": [0, 0, 0], "max": [0.3, 0.4, 0.3]}})");
    const std::vector<std::string> args = {
        (dir / "scene.json").string(), "--headless", "--quiet", "--steps", "8", "--stats-json",
        (dir / "stats.json").string(), "--check"};
    RunResult run = play(dir, args);
    EXPECT_EQ(run.code, 1) << shown(run);
    EXPECT_NE(run.err.find("[body-density]"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("a dynamic body went non-finite or its centre left the domain box"),
              std::string::npos)
        << run.err;
    EXPECT_NE(run.err.find("or a body was lost"), std::string::npos) << run.err;
    const auto stats = nlohmann::json::parse(readBytes(dir / "stats.json"));
    const auto& last = stats["steps"].back();
    EXPECT_GT(last["bodyFaults"].get<std::uint64_t>(), 0u) << last;
    const auto& position = last["bodies"][0]["centreOfMass"];
    for (int a = 0; a < 3; ++a) {
        const double x = position[a].get<double>();
        EXPECT_TRUE(std::isfinite(x) && x >= 0.0 && x <= 0.4) << "axis " << a << ": " << x;
    }

    // --strict refuses the density before anything runs.
    std::vector<std::string> strict = args;
    strict.push_back("--strict");
    fs::remove(dir / "stats.json");
    run = play(dir, strict);
    EXPECT_EQ(run.code, 2) << shown(run);
    EXPECT_NE(run.err.find("nothing was run"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(dir / "stats.json"));
}

// --- No OpenGL 4.5 --------------------------------------------------------------------------

TEST(RuntimeFault, WithoutAnOpenGl45ContextExitsThreeSayingSo) {
    const fs::path dir = freshDir("no-gl");
    writeText(dir / "scene.json", sceneText("{}"));
    const std::vector<std::vector<std::string>> environments = {
        // Mesa offers only OpenGL 3.3: a context, but not the version the solver needs.
        {"MESA_GL_VERSION_OVERRIDE=3.3", "MESA_GLSL_VERSION_OVERRIDE=330"},
        // No EGL implementation at all (glvnd finds no vendor library).
        {"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl_vendor.json",
         "__EGL_VENDOR_LIBRARY_DIRS=/nonexistent"},
        // A platform name no driver has.
        {"SLUICE_EGL_PLATFORM=nowhere"},
    };
    for (const auto& env : environments) {
        SCOPED_TRACE(env.front());
        const RunResult run =
            play(dir, {(dir / "scene.json").string(), "--headless", "--steps", "1"}, env);
        EXPECT_EQ(run.code, 3) << shown(run);
        EXPECT_NE(run.err.find("[NoGlContext]"), std::string::npos) << run.err;
    }
}

} // namespace
} // namespace sluice::reliability
