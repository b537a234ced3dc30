// A bake killed with SIGKILL at any moment, the write included, leaves the previous asset whole
// and no temporary file in the output folder (but in the two system calls between naming the
// complete file and the rename), and the next bake succeeds and removes any.
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "ReliabilityTest.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::reliability {
namespace {

using Clock = std::chrono::steady_clock;

/// The mesh, the previous asset and what a complete bake writes, shared by the tests.
struct Fixture {
    fs::path dir;
    fs::path mesh;
    std::string previous;   ///< bytes of the asset already in place before each killed bake
    std::string complete;   ///< bytes a complete bake writes (bakes are deterministic)
    double bakeSeconds = 0; ///< wall time of one complete bake
};

std::vector<std::string> bakeArgs(const Fixture& f, const fs::path& output, int resolution) {
    return {SLUICE_BAKE_EXE,
            "bake",
            f.mesh.string(),
            "-o",
            output.string(),
            "--resolution",
            std::to_string(resolution),
            "--quiet"};
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true; // the asan preset: bakes are several times slower
#else
constexpr bool kSanitized = false;
#endif

// Resolution of the bake that is killed: about 360k grid points, a 1.4 MB asset (170k points,
// 0.7 MB under ASan).
constexpr int kResolution = kSanitized ? 48 : 64;
// Kills spread over the bake.
constexpr int kRandomKills = kSanitized ? 6 : 10;

const Fixture& fixture() {
    static const Fixture fixed = [] {
        Fixture made;
        // Per process: ctest runs the tests of this file side by side.
        made.dir = freshDir("crash-safe-" + std::to_string(::getpid()));
        made.mesh = made.dir / "sphere.obj";
        writeSphereObj(made.mesh, 1.0, 48, 24);
        const fs::path previous = made.dir / "previous.slc";
        Spawned small(bakeArgs(made, previous, 8), made.dir / "out.txt", made.dir / "err.txt");
        small.wait();
        made.previous = readBytes(previous);
        const fs::path complete = made.dir / "complete.slc";
        const auto start = Clock::now();
        Spawned full(bakeArgs(made, complete, kResolution), made.dir / "out.txt",
                     made.dir / "err.txt");
        full.wait();
        made.bakeSeconds = std::chrono::duration<double>(Clock::now() - start).count();
        made.complete = readBytes(complete);
        return made;
    }();
    // The folder holds a dozen assets of 1.4 MB: gone when the test process ends.
    struct RemoveAtExit {
        fs::path dir;
        ~RemoveAtExit() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    };
    static const RemoveAtExit cleanup{fixed.dir};
    return fixed;
}

/// A fresh output folder holding only the previous asset, as collider.slc.
fs::path outputWithPrevious(const std::string& name) {
    const Fixture& f = fixture();
    const fs::path out = f.dir / name;
    fs::remove_all(out);
    fs::create_directories(out);
    writeText(out / "collider.slc", f.previous);
    return out;
}

/// Checks the state a bake killed as process `pid` leaves: the asset is the previous one or the
/// complete new one, whole. Nothing else is in the folder, but for one case: killed in the two
/// system calls between naming its complete, fsync'd file and renaming it, the bake leaves
/// ".collider.slc.tmp-<pid>-...", holding the whole new asset; the next bake removes it
/// (expectALaterBakeSucceeds). Returns which asset, and counts such leftovers in `leftovers`.
std::string checkAfterKill(const fs::path& out, pid_t pid, int& leftovers) {
    const Fixture& f = fixture();
    const std::string leftover = ".collider.slc.tmp-" + std::to_string(pid) + "-";
    for (const std::string& name : listDir(out)) {
        if (name == "collider.slc")
            continue;
        if (name.rfind(leftover, 0) == 0 && readBytes(out / name) == f.complete) {
            ++leftovers;
            continue;
        }
        ADD_FAILURE() << "a killed bake left " << name << " behind";
    }
    const std::string now = readBytes(out / "collider.slc");
    if (now == f.previous)
        return "previous";
    if (now == f.complete)
        return "complete";
    ADD_FAILURE() << "collider.slc is neither the previous asset nor the complete new one ("
                  << now.size() << " bytes)";
    return "damaged";
}

/// A later bake into the same folder succeeds, writes the complete asset and nothing else.
void expectALaterBakeSucceeds(const fs::path& out) {
    const Fixture& f = fixture();
    Spawned later(bakeArgs(f, out / "collider.slc", kResolution), out / "../later-out.txt",
                  out / "../later-err.txt");
    const int status = later.wait();
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << readBytes(out / "../later-err.txt");
    EXPECT_EQ(readBytes(out / "collider.slc"), f.complete);
    EXPECT_EQ(listDir(out), std::set<std::string>{"collider.slc"});
}

TEST(CrashSafeWrite, TheFixtureBakesTwoDifferentValidAssets) {
    const Fixture& f = fixture();
    ASSERT_FALSE(f.previous.empty());
    ASSERT_FALSE(f.complete.empty());
    EXPECT_NE(f.previous, f.complete);
    const auto* bytes = reinterpret_cast<const std::byte*>(f.complete.data());
    EXPECT_TRUE(format::decodeAsset(std::span(bytes, f.complete.size()), "complete").ok());
    std::printf("one bake: %.2f s, %zu bytes\n", f.bakeSeconds, f.complete.size());
}

TEST(CrashSafeWrite, SigkillDuringTheWriteKeepsThePreviousAssetAndLeavesNoTemporaryFile) {
    // The bake is stopped the moment it holds a file open in the output folder (the temporary
    // file it writes the asset to), checked, then killed: the write window every time.
    const Fixture& f = fixture();
    int caught = 0, leftovers = 0;
    constexpr int kWanted = 3, kAttempts = 12;
    for (int attempt = 0; attempt < kAttempts && caught < kWanted; ++attempt) {
        SCOPED_TRACE("attempt " + std::to_string(attempt));
        const fs::path out = outputWithPrevious("write-" + std::to_string(attempt));
        Spawned bake(bakeArgs(f, out / "collider.slc", kResolution), out / "../write-out.txt",
                     out / "../write-err.txt");
        ASSERT_TRUE(bake.started());
        bool writing = false;
        while (!bake.exited()) {
            if (holdsFileIn(bake.pid(), out)) {
                if (!bake.stop())
                    break;                              // it finished meanwhile
                writing = holdsFileIn(bake.pid(), out); // still inside the write, stopped
                if (writing)
                    break;
                bake.kill(SIGCONT);
            }
        }
        if (!writing) {
            bake.kill(SIGCONT);
            bake.wait();
            continue; // the write was too quick to catch this time
        }
        EXPECT_EQ(readBytes(out / "collider.slc"), f.previous)
            << "the asset changed before the new one was complete";
        bake.kill(SIGKILL);
        bake.wait();
        EXPECT_EQ(checkAfterKill(out, bake.pid(), leftovers), "previous");
        ++caught;
        expectALaterBakeSucceeds(out);
    }
    EXPECT_EQ(caught, kWanted) << "the write window was caught only " << caught << " times";
    // Stopped inside the write, the bake is almost always still writing its unnamed file.
    EXPECT_LT(leftovers, caught) << "every kill came between the naming and the rename";
    std::printf("%d of %d kills in the write left a named complete file\n", leftovers, caught);
}

TEST(CrashSafeWrite, SigkillAtMomentsAcrossTheWholeBakeLeavesTheOldOrTheNewAssetWhole) {
    const Fixture& f = fixture();
    constexpr int kKills = kRandomKills;
    int previous = 0, complete = 0, leftovers = 0;
    for (int i = 0; i < kKills; ++i) {
        // Spread over the import, the bake, the encode and the write, a little past the end.
        const double delay = f.bakeSeconds * 1.1 * (i + 0.5) / kKills;
        SCOPED_TRACE("kill after " + std::to_string(delay) + " s");
        const fs::path out = outputWithPrevious("random-" + std::to_string(i));
        Spawned bake(bakeArgs(f, out / "collider.slc", kResolution), out / "../random-out.txt",
                     out / "../random-err.txt");
        ASSERT_TRUE(bake.started());
        std::this_thread::sleep_for(std::chrono::duration<double>(delay));
        bake.kill(SIGKILL);
        bake.wait();
        const std::string state = checkAfterKill(out, bake.pid(), leftovers);
        previous += state == "previous";
        complete += state == "complete";
        expectALaterBakeSucceeds(out);
    }
    std::printf("%d kills left the previous asset, %d the complete new one, %d a named complete "
                "file\n",
                previous, complete, leftovers);
    EXPECT_EQ(previous + complete, kKills);
    EXPECT_GT(previous, 0);
}

} // namespace
} // namespace sluice::reliability
