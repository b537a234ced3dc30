// One table of simulation parameter ranges (SimulationLimits.h): the scene reader refuses
// exactly what checkSimulationParams refuses, which the solver's setParameters (and so the
// viewer's panel and Python) use, for every parameter, just outside and just inside.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "sluice/format/scene/SceneIO.h"
#include "sluice/format/scene/SimulationLimits.h"

namespace sluice::format {
namespace {

// The simulation parameters a scene with `simulation` in its "simulation" object reads to
// (every default filled in), or the reader's error.
Result<Scene> sceneWith(const std::string& simulation) {
    return parseScene(R"({"simulation": {"spacing": 0.02)" + simulation +
                          R"(}, "fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}]})",
                      "limits.json");
}

struct Probe {
    const char* name;
    double below; // just outside the range at spacing 0.02 (h 0.04 unless given), or NaN
    double inside;
    double above; // or NaN
};

// Ranges at spacing 0.02, kernelRadius 0.04: kernelRadius [0.03, 0.08], scorrDeltaQ [0, 0.04).
const Probe kProbes[] = {
    {"kernelRadius", 0.0299, 0.05, 0.0801},
    {"restDensity", 0.0, 1000.0, NAN},
    {"timeStep", 0.0, 0.01, 5.0},
    {"targetDensityError", -0.001, 0.01, 1.5},
    {"relaxation", -0.1, 0.01, 101.0},
    {"scorrK", -0.1, 0.1, NAN},
    {"scorrN", 0.5, 4.0, 9.0},
    {"scorrDeltaQ", -0.001, 0.01, 0.04},
    {"xsph", -0.01, 0.02, 5.0},
    {"vorticity", -0.1, 0.0, NAN},
    {"substeps", 0.0, 4.0, 1001.0},
    {"minIterations", 0.0, 2.0, 1001.0},
};

std::string key(const Probe& p, double v) {
    return std::string(R"(, ")") + p.name + R"(": )" + std::to_string(v);
}

TEST(SimulationLimits, TheSceneReaderAndTheCheckRefuseTheSameValues) {
    auto base = sceneWith("");
    ASSERT_TRUE(base) << base.error().message();
    EXPECT_TRUE(checkSimulationParams(base->simulation)) << "the defaults are in range";
    for (const Probe& p : kProbes) {
        SCOPED_TRACE(p.name);
        for (const double v : {p.below, p.inside, p.above}) {
            if (std::isnan(v))
                continue;
            const bool inRange = v == p.inside;
            auto read = sceneWith(key(p, v));
            EXPECT_EQ(bool(read), inRange) << v << ": "
                                           << (read ? std::string("read") : read.error().message());
            // The same value set on the defaults, as the solver's setParameters gets it.
            SimulationParams params = base->simulation;
            const std::string name = p.name;
            if (name == "substeps")
                params.substeps = std::uint32_t(v);
            else if (name == "minIterations")
                params.minIterations = std::uint32_t(v);
            else if (name == "kernelRadius")
                params.kernelRadius = float(v), params.scorrDeltaQ = 0.0f;
            else if (name == "restDensity")
                params.restDensity = float(v);
            else if (name == "timeStep")
                params.timeStep = float(v);
            else if (name == "targetDensityError")
                params.targetDensityError = float(v);
            else if (name == "relaxation")
                params.relaxation = float(v);
            else if (name == "scorrK")
                params.scorrK = float(v);
            else if (name == "scorrN")
                params.scorrN = float(v);
            else if (name == "scorrDeltaQ")
                params.scorrDeltaQ = float(v);
            else if (name == "xsph")
                params.xsph = float(v);
            else if (name == "vorticity")
                params.vorticity = float(v);
            auto checked = checkSimulationParams(params);
            EXPECT_EQ(bool(checked), inRange) << v;
            if (!checked) {
                EXPECT_EQ(checked.error().code, ErrorCode::InvalidArgument);
                EXPECT_NE(checked.error().detail.find(name + ": "), std::string::npos)
                    << checked.error().detail;
            }
        }
    }
}

TEST(SimulationLimits, NamesWhatIsWrong) {
    auto base = sceneWith("");
    ASSERT_TRUE(base) << base.error().message();
    SimulationParams p = base->simulation;
    p.xsph = 5.0f;
    auto xsph = checkSimulationParams(p);
    ASSERT_FALSE(xsph);
    EXPECT_EQ(xsph.error().detail, "xsph: 5 is out of range [0, 1]");
    p = base->simulation;
    p.gravity.y = NAN;
    auto gravity = checkSimulationParams(p);
    ASSERT_FALSE(gravity);
    EXPECT_EQ(gravity.error().code, ErrorCode::NonFinite);
    p = base->simulation;
    p.maxIterations = 1;
    p.minIterations = 2;
    auto iterations = checkSimulationParams(p);
    ASSERT_FALSE(iterations);
    EXPECT_NE(iterations.error().detail.find("less than minIterations"), std::string::npos);
}

} // namespace
} // namespace sluice::format
