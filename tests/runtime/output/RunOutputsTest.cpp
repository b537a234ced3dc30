// Output paths of sluice-play: folders created before the run, and nothing created when any
// output is wrong.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "ProgramRun.h"

#include "output/RunOutputs.h"

namespace sluice::rt {
namespace {

namespace fs = std::filesystem;

using testrun::tempDir;

TEST(RunOutputs, CreatesTheParentsOfFilesAndTheFoldersThemselves) {
    const fs::path dir = tempDir("outputs-create");
    const auto ok = prepareRunOutputs({{"--stats-json", (dir / "a/b/stats.json").string(), false},
                                       {"--dump-ply", (dir / "c/ply").string(), true},
                                       {"--video", "", false}});
    ASSERT_TRUE(ok) << ok.error().message();
    EXPECT_TRUE(fs::is_directory(dir / "a/b"));
    EXPECT_FALSE(fs::exists(dir / "a/b/stats.json"));
    EXPECT_TRUE(fs::is_directory(dir / "c/ply"));
}

TEST(RunOutputs, RejectsAFileOutputThatIsAFolderNamingTheOptionAndPath) {
    const fs::path dir = tempDir("outputs-folder");
    const auto ok = prepareRunOutputs({{"--stats-json", dir.string(), false}});
    ASSERT_FALSE(ok);
    EXPECT_EQ(ok.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(ok.error().detail.find("--stats-json " + dir.string() + ": is a folder"),
              std::string::npos)
        << ok.error().detail;
}

TEST(RunOutputs, RejectsAFolderOutputThatIsAFile) {
    const fs::path dir = tempDir("outputs-file");
    std::ofstream(dir / "frames") << "x";
    const auto ok = prepareRunOutputs({{"--frames", (dir / "frames").string(), true}});
    ASSERT_FALSE(ok);
    EXPECT_NE(ok.error().detail.find("is a file; give a folder"), std::string::npos)
        << ok.error().detail;
}

TEST(RunOutputs, RejectsAPathThroughAFileAndCreatesNothingForTheOthers) {
    const fs::path dir = tempDir("outputs-through-file");
    std::ofstream(dir / "plain") << "x";
    const auto ok = prepareRunOutputs({{"--dump-ply", (dir / "ply").string(), true},
                                       {"--stats-json", (dir / "plain/s.json").string(), false}});
    ASSERT_FALSE(ok);
    EXPECT_NE(ok.error().detail.find("plain is a file, not a folder"), std::string::npos)
        << ok.error().detail;
    EXPECT_FALSE(fs::exists(dir / "ply")); // checked all first: nothing created
}

TEST(RunOutputs, AcceptsAFileInTheWorkingFolder) {
    const auto ok = prepareRunOutputs({{"--bench-json", "bench-result.json", false}});
    EXPECT_TRUE(ok) << ok.error().message();
}

} // namespace
} // namespace sluice::rt
