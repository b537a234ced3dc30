// SIGINT (Ctrl-C) and SIGTERM (kill, a job scheduler) end a headless sluice-play run after the
// current step, with every output it was asked for written as far as it got: statistics, PLY
// frames, the body table, the video closed; exit 130 or 143. sluice-play runs as its own
// process here, so the signal reaches it as it would from a terminal.
#include <chrono>
#include <ostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ReliabilityTest.h"

namespace sluice::reliability {
namespace {

const fs::path kAssets = SLUICE_BUILD_ASSETS_DIR;

/// The number of statistics rows printed so far (the table is flushed row by row when
/// stdout is a file or a pipe): the lines that start with a step number.
int tableRows(const fs::path& out) {
    std::istringstream in(readBytes(out));
    int rows = 0;
    for (std::string line; std::getline(in, line);) {
        std::istringstream words(line);
        unsigned long long step = 0;
        double time = 0.0;
        if (words >> step >> time && line.find("steps in") == std::string::npos)
            ++rows;
    }
    return rows;
}

struct SignalCase {
    int signal;
    int exitCode;
    const char* name;
};

void PrintTo(const SignalCase& c, std::ostream* os) {
    *os << c.name;
}

class PlayInterrupt : public ::testing::TestWithParam<SignalCase> {};

TEST_P(PlayInterrupt, EndsAfterTheCurrentStepWithEveryOutputWrittenUpToIt) {
    const SignalCase c = GetParam();
    const fs::path dir = freshDir(std::string("interrupt-") + c.name);
    const std::uint64_t steps = 100000;
    Spawned play({SLUICE_PLAY_EXE, (kAssets / "float.json").string(), "--headless", "--steps",
                  std::to_string(steps), "--stats-every", "1", "--stats-json",
                  (dir / "stats.json").string(), "--dump-ply", (dir / "ply").string(),
                  "--dump-every", "2", "--bodies-csv", (dir / "bodies.csv").string()},
                 dir / "out.txt", dir / "err.txt");
    ASSERT_TRUE(play.started());
    // Three rows in the table: the run is stepping (and its table reaches a file as it goes).
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(3);
    while (tableRows(dir / "out.txt") < 3 && !play.exited() &&
           std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_GE(tableRows(dir / "out.txt"), 3)
        << readBytes(dir / "out.txt") << readBytes(dir / "err.txt");
    play.kill(c.signal);
    const int status = play.wait();
    const std::string err = readBytes(dir / "err.txt");
    ASSERT_TRUE(WIFEXITED(status)) << "killed by the signal instead of ending the run\n" << err;
    EXPECT_EQ(WEXITSTATUS(status), c.exitCode) << err;

    const auto stats = nlohmann::json::parse(readBytes(dir / "stats.json"));
    ASSERT_TRUE(stats.contains("interrupted")) << stats.dump();
    EXPECT_EQ(stats["interrupted"]["signal"].get<std::string>(), c.name);
    const std::uint64_t last = stats["interrupted"]["afterStep"].get<std::uint64_t>();
    EXPECT_GE(last, 3u);
    EXPECT_LT(last, steps);
    EXPECT_EQ(stats["interrupted"]["ofSteps"].get<std::uint64_t>(), steps);
    // Every step to the last has its row: the last one too, recorded when the signal came.
    ASSERT_EQ(stats["steps"].size(), last);
    EXPECT_EQ(stats["steps"].back()["step"].get<std::uint64_t>(), last);
    EXPECT_NE(err.find(std::string(c.name) + ": stopped after step " + std::to_string(last) +
                       " of " + std::to_string(steps)),
              std::string::npos)
        << err;

    // The PLY frames of every even step to the last, each with its body transforms.
    for (std::uint64_t step = 0; step <= last; step += 2) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%06llu", static_cast<unsigned long long>(step));
        EXPECT_TRUE(fs::exists(dir / "ply" / (std::string(name) + ".ply"))) << name;
        EXPECT_TRUE(fs::exists(dir / "ply" / (std::string(name) + ".bodies.json"))) << name;
    }
    // The body table: header, then four bodies at step 0 and at every recorded step.
    std::istringstream csv(readBytes(dir / "bodies.csv"));
    std::vector<std::string> lines;
    for (std::string line; std::getline(csv, line);)
        lines.push_back(line);
    ASSERT_EQ(lines.size(), 1 + 4 * (last + 1));
    EXPECT_EQ(lines.back().substr(0, lines.back().find(',')), std::to_string(last));
    // Nothing half-written: no temporary files beside the outputs.
    for (const fs::path& folder : {dir, dir / "ply"})
        for (const std::string& name : listDir(folder))
            EXPECT_EQ(name.find(".tmp"), std::string::npos) << folder / name;
}

INSTANTIATE_TEST_SUITE_P(Signals, PlayInterrupt,
                         ::testing::Values(SignalCase{SIGINT, 130, "SIGINT"},
                                           SignalCase{SIGTERM, 143, "SIGTERM"}),
                         [](const auto& param) { return std::string(param.param.name); });

} // namespace
} // namespace sluice::reliability
