// `sluice-bake bake --profile` accounts for the whole process; the GPU program cache is used,
// survives damaged files and can be turned off. Needs OpenGL 4.5 (llvmpipe is enough).
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include "TestMeshes.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/support/ExitCodes.h"
#include "sluice/format/support/Hash.h"
#include "sluice/format/support/Sanitizers.h"

extern char** environ;

namespace sluice::bake {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// One run of sluice-bake, timed from outside.
struct TimedRun {
    int code = -1;
    double wall = 0.0; ///< [s] spawn to exit
    double cpu = 0.0;  ///< [s] of the process and its waited-for children (wait4)
    std::string out, err;
};

/// Runs sluice-bake with `args` and `env` added to this process's environment, without a shell
/// (so the time measured is the program's own, start to exit).
TimedRun runBake(const fs::path& dir, const std::vector<std::string>& args,
                 const std::vector<std::string>& env = {}) {
    std::vector<std::string> all = {SLUICE_BAKE_EXE};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& arg : all)
        argv.push_back(arg.data());
    argv.push_back(nullptr);
    std::vector<std::string> environment(env.begin(), env.end());
    for (char** e = environ; *e != nullptr; ++e)
        environment.emplace_back(*e); // the first of a name wins, so `env` overrides
    std::vector<char*> envp;
    for (std::string& entry : environment)
        envp.push_back(entry.data());
    envp.push_back(nullptr);
    const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    TimedRun run;
    const auto start = std::chrono::steady_clock::now();
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0)
        return run;
    int status = 0;
    rusage usage{};
    while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
    }
    run.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.cpu = double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
              1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = readText(out);
    run.err = readText(err);
    return run;
}

std::string shown(const TimedRun& run) {
    return "exit " + std::to_string(run.code) + "\nstdout:\n" + run.out + "\nstderr:\n" + run.err;
}

/// A closed sphere mesh of 320 triangles in `folder`.
fs::path sphereMesh(const std::string& folder) {
    return testmesh::writeTempObj(testmesh::icoSphereSoup({0, 0, 0}, 1.0, 2), folder, "s.obj");
}

std::vector<std::string> gpuBake(const fs::path& mesh, const fs::path& asset) {
    return {"bake", mesh.string(), "-o", asset.string(), "--backend", "gpu", "--resolution", "16",
            "--json", "--profile"};
}

/// The names of the entries of a profile list ("phases" or "overlapped").
std::vector<std::string> names(const nlohmann::json& list) {
    std::vector<std::string> out;
    for (const nlohmann::json& phase : list)
        out.push_back(phase["name"].get<std::string>());
    return out;
}

bool hasPhaseStartingWith(const std::vector<std::string>& phases, const std::string& prefix) {
    return std::any_of(phases.begin(), phases.end(),
                       [&](const std::string& name) { return name.rfind(prefix, 0) == 0; });
}

TEST(CliProfile, ThePhasesCoverTheWholeProcessFromStartToTheWrittenFile) {
    const fs::path dir = testmesh::tempDir("cli-profile");
    const fs::path mesh = sphereMesh("cli-profile");
    const TimedRun run = runBake(dir, gpuBake(mesh, dir / "s.slc"),
                                 {"XDG_CACHE_HOME=" + (dir / "cache").string()});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    const nlohmann::json profile = nlohmann::json::parse(run.out)["profile"];

    // Every step of the bake is a phase of its own.
    const std::vector<std::string> phases = names(profile["phases"]);
    for (const char* step :
         {"start-up", "argument checks", "import: file checks", "import: file hash",
          "GPU context", "program cache", "import: wait for the isolated child",
          "mesh diagnostics: topology", "grid plan", "gpu: prepare the soup", "gpu: BVH build",
          "gpu: compile and link programs", "gpu: upload", "gpu: passes", "gpu: readback",
          "gpu: asset", "wait for the self-intersection test", "release the GPU context",
          "encode", "write"})
        EXPECT_TRUE(hasPhaseStartingWith(phases, step)) << step << " missing from\n" << run.out;
    const std::vector<std::string> overlapped = names(profile["overlapped"]);
    EXPECT_TRUE(hasPhaseStartingWith(overlapped, "import: isolated child process")) << run.out;
    EXPECT_TRUE(hasPhaseStartingWith(overlapped, "mesh diagnostics: self-intersection test"))
        << run.out;

    double wallSum = 0.0, cpuSum = 0.0;
    for (const nlohmann::json& phase : profile["phases"]) {
        EXPECT_GE(phase["wallSeconds"].get<double>(), 0.0) << phase;
        EXPECT_GE(phase["cpuSeconds"].get<double>(), 0.0) << phase;
        wallSum += phase["wallSeconds"].get<double>();
        cpuSum += phase["cpuSeconds"].get<double>();
    }
    const double total = profile["totalSeconds"].get<double>();
    EXPECT_NEAR(profile["phasesSeconds"].get<double>(), wallSum, 1e-9);
    EXPECT_NEAR(profile["unaccountedSeconds"].get<double>(), total - wallSum, 1e-9);
    // The total is the process's age from the kernel's start time (10 ms ticks), the phases are
    // laps of another clock: they agree to a tick.
    EXPECT_NEAR(total, wallSum, 0.02) << run.out;
    // Measured from outside, the process took its total plus its spawn and its exit after the
    // last phase: nothing of consequence escapes the phases.
    EXPECT_LE(total, run.wall + 0.011) << run.out;
    EXPECT_GE(total, run.wall - 0.05 - 0.1 * run.wall)
        << "the phases miss " << run.wall - total << " s of " << run.wall << " s\n"
        << run.out;
    // The same for CPU time: the phases' sum is the process's (and its import child's) CPU time
    // at the last phase; the exit after it costs a few milliseconds.
    EXPECT_LE(cpuSum, run.cpu + 0.02) << run.out;
    EXPECT_GE(cpuSum, 0.8 * run.cpu - 0.02) << "CPU " << run.cpu << " s\n" << run.out;
}

TEST(CliProfile, TheSummaryListsThePhasesAndTheRemainder) {
    const fs::path dir = testmesh::tempDir("cli-profile-text");
    const fs::path mesh = sphereMesh("cli-profile-text");
    const TimedRun run = runBake(dir,
                                 {"bake", mesh.string(), "-o", (dir / "s.slc").string(),
                                  "--backend", "cgal", "--resolution", "8", "--profile"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("profile "), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("s unaccounted"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("mesh diagnostics"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("cgal bake"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("write (atomic, fsync)"), std::string::npos) << run.out;
}

/// The "gpu"."programCache" object of a bake's JSON.
nlohmann::json programCache(const TimedRun& run) {
    return nlohmann::json::parse(run.out)["gpu"]["programCache"];
}

std::vector<fs::path> cacheFiles(const fs::path& dir) {
    std::vector<fs::path> files;
    if (fs::is_directory(dir))
        for (const fs::directory_entry& entry : fs::directory_iterator(dir))
            files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

/// Bakes with an empty cache in dir/cache and checks what it stored; skips the test where the
/// driver offers no program binary format (Mesa with its shader cache disabled).
bool warmCache(const fs::path& dir, const fs::path& mesh, int& programs) {
    const TimedRun first = runBake(dir, gpuBake(mesh, dir / "first.slc"),
                                   {"XDG_CACHE_HOME=" + (dir / "cache").string()});
    EXPECT_EQ(first.code, kExitOk) << shown(first);
    if (first.code != kExitOk)
        return false;
    const nlohmann::json cache = programCache(first);
    if (cache["binaryFormats"].get<int>() == 0)
        return false;
    EXPECT_TRUE(cache["enabled"].get<bool>()) << cache;
    EXPECT_EQ(cache["dir"], (dir / "cache" / "sluice").string());
    EXPECT_EQ(cache["hits"], 0);
    programs = cache["misses"].get<int>();
    EXPECT_GT(programs, 0) << cache;
    EXPECT_EQ(cache["stored"], programs);
    EXPECT_EQ(int(cacheFiles(dir / "cache" / "sluice").size()), programs);
    return true;
}

TEST(ProgramCache, ASecondBakeLoadsEveryProgramFromTheCache) {
    const fs::path dir = testmesh::tempDir("program-cache");
    const fs::path mesh = sphereMesh("program-cache");
    int programs = 0;
    if (!warmCache(dir, mesh, programs))
        GTEST_SKIP() << "the driver offers no program binary format";
    const TimedRun second = runBake(dir, gpuBake(mesh, dir / "second.slc"),
                                    {"XDG_CACHE_HOME=" + (dir / "cache").string()});
    ASSERT_EQ(second.code, kExitOk) << shown(second);
    const nlohmann::json cache = programCache(second);
    EXPECT_EQ(cache["hits"], programs) << cache;
    EXPECT_EQ(cache["misses"], 0) << cache;
    EXPECT_EQ(cache["stored"], 0) << cache;
    EXPECT_EQ(readText(dir / "first.slc"), readText(dir / "second.slc"));
}

TEST(ProgramCache, DamagedOrForeignFilesAreIgnoredRebuiltAndTheBakeIsTheSame) {
    const fs::path dir = testmesh::tempDir("program-cache-damaged");
    const fs::path mesh = sphereMesh("program-cache-damaged");
    int programs = 0;
    if (!warmCache(dir, mesh, programs))
        GTEST_SKIP() << "the driver offers no program binary format";
    const std::vector<fs::path> files = cacheFiles(dir / "cache" / "sluice");
    // Each file damaged another way: empty, truncated, a flipped byte of the binary, another
    // key (a file of another shader or driver), a binary the driver must refuse under a
    // correct checksum.
    for (std::size_t n = 0; n < files.size(); ++n) {
        std::string bytes = readText(files[n]);
        ASSERT_GT(bytes.size(), 48u);
        switch (n % 5) {
        case 0:
            bytes.clear();
            break;
        case 1:
            bytes.resize(bytes.size() / 2);
            break;
        case 2:
            bytes[bytes.size() - 7] ^= 0x5a;
            break;
        case 3:
            bytes[9] ^= 0x01;
            break;
        default: {
            for (std::size_t i = 40; i < bytes.size(); ++i)
                bytes[i] = char((i * 131) & 0xff);
            const std::uint64_t hash = format::xxh3(std::as_bytes(
                std::span<const char>(bytes.data() + 40, bytes.size() - 40)));
            std::memcpy(bytes.data() + 32, &hash, sizeof hash);
        }
        }
        std::ofstream(files[n], std::ios::binary | std::ios::trunc) << bytes;
    }
    const TimedRun damaged = runBake(dir, gpuBake(mesh, dir / "damaged.slc"),
                                     {"XDG_CACHE_HOME=" + (dir / "cache").string()});
    ASSERT_EQ(damaged.code, kExitOk) << shown(damaged);
    const nlohmann::json cache = programCache(damaged);
    EXPECT_EQ(cache["hits"], 0) << cache;
    EXPECT_EQ(cache["rejected"], programs) << cache;
    EXPECT_EQ(cache["misses"], programs) << cache;
    EXPECT_EQ(cache["stored"], programs) << cache;
    EXPECT_EQ(readText(dir / "first.slc"), readText(dir / "damaged.slc"));

    // Rebuilt: the next bake hits again.
    const TimedRun again = runBake(dir, gpuBake(mesh, dir / "again.slc"),
                                   {"XDG_CACHE_HOME=" + (dir / "cache").string()});
    ASSERT_EQ(again.code, kExitOk) << shown(again);
    EXPECT_EQ(programCache(again)["hits"], programs) << again.out;
}

TEST(ProgramCache, TurnedOffByTheOptionOrTheEnvironmentItCompilesAndWritesNothing) {
    const fs::path dir = testmesh::tempDir("program-cache-off");
    const fs::path mesh = sphereMesh("program-cache-off");
    std::vector<std::string> noCache = gpuBake(mesh, dir / "option.slc");
    noCache.push_back("--no-program-cache");
    const TimedRun option =
        runBake(dir, noCache, {"XDG_CACHE_HOME=" + (dir / "cache").string()});
    ASSERT_EQ(option.code, kExitOk) << shown(option);
    EXPECT_FALSE(programCache(option)["enabled"].get<bool>()) << option.out;
    EXPECT_EQ(programCache(option)["hits"], 0);

    const TimedRun environment =
        runBake(dir, gpuBake(mesh, dir / "environment.slc"),
                {"XDG_CACHE_HOME=" + (dir / "cache").string(), "SLUICE_PROGRAM_CACHE=0"});
    ASSERT_EQ(environment.code, kExitOk) << shown(environment);
    const nlohmann::json cache = programCache(environment);
    EXPECT_FALSE(cache["enabled"].get<bool>());
    EXPECT_NE(cache["offReason"].get<std::string>().find("SLUICE_PROGRAM_CACHE"),
              std::string::npos)
        << cache;
    EXPECT_TRUE(cacheFiles(dir / "cache" / "sluice").empty());

    // The same field as with a cache.
    const TimedRun cached = runBake(dir, gpuBake(mesh, dir / "cached.slc"),
                                    {"XDG_CACHE_HOME=" + (dir / "cache").string()});
    ASSERT_EQ(cached.code, kExitOk) << shown(cached);
    EXPECT_EQ(readText(dir / "option.slc"), readText(dir / "cached.slc"));
    EXPECT_EQ(readText(dir / "environment.slc"), readText(dir / "cached.slc"));
}

TEST(ProgramCache, AnUnwritableCacheFolderTurnsItOffAndTheBakeSucceeds) {
    const fs::path dir = testmesh::tempDir("program-cache-unwritable");
    const fs::path mesh = sphereMesh("program-cache-unwritable");
    std::ofstream(dir / "file") << "not a folder";
    std::vector<std::string> env = {"XDG_CACHE_HOME=" + (dir / "file").string()};
    // Under ASan this child's exit-time leak check crashes inside LeakSanitizer while it reads
    // the thread-local storage of Mesa's threads ("Tracer caught signal 11", exit 1; with
    // LSAN_OPTIONS=use_tls=0 it runs), depending on the binary's layout: a fault of the
    // sanitizer runtime, not of the bake. Leaks are still checked by every other test.
    if (kAddressSanitizer)
        env.push_back("ASAN_OPTIONS=detect_leaks=0");
    const TimedRun run = runBake(dir, gpuBake(mesh, dir / "s.slc"), env);
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_FALSE(programCache(run)["enabled"].get<bool>()) << run.out;
}

TEST(CliGpuBake, AMeshThatIntersectsItselfIsSignedByTheWindingNumberAsBefore) {
    // Two overlapping closed boxes: closed, self-intersecting. The GPU bake starts as parity
    // while the self-intersection test runs, and bakes again with the winding number.
    TriangleSoup soup = testmesh::boxSoup({0, 0, 0}, {1, 1, 1});
    const TriangleSoup second = testmesh::boxSoup({0.5, 0.3, 0.2}, {1.5, 1.3, 1.2});
    const std::uint32_t offset = std::uint32_t(soup.positions.size());
    soup.positions.insert(soup.positions.end(), second.positions.begin(), second.positions.end());
    for (const glm::uvec3& t : second.triangles)
        soup.triangles.push_back(t + offset);
    const fs::path dir = testmesh::tempDir("cli-self-intersecting");
    const fs::path mesh = testmesh::writeTempObj(soup, "cli-self-intersecting", "two.obj");
    const auto bake = [&](const char* sign, const char* file) {
        return runBake(dir, {"bake", mesh.string(), "-o", (dir / file).string(), "--backend",
                             "gpu", "--resolution", "16", "--sign", sign, "--quiet"});
    };
    ASSERT_EQ(bake("auto", "auto.slc").code, kExitOk);
    ASSERT_EQ(bake("winding", "winding.slc").code, kExitOk);
    Result<format::ColliderAsset> automatic = format::readAsset(dir / "auto.slc");
    Result<format::ColliderAsset> winding = format::readAsset(dir / "winding.slc");
    ASSERT_TRUE(automatic.ok() && winding.ok());
    EXPECT_TRUE(automatic->meta.mesh.selfIntersecting);
    EXPECT_TRUE(automatic->meta.mesh.closed);
    EXPECT_EQ(automatic->meta.bake.signUsed, format::SignMethod::Winding);
    EXPECT_EQ(automatic->distances, winding->distances);

    // A closed mesh that does not intersect itself keeps parity and says so.
    const fs::path sphere = sphereMesh("cli-self-intersecting");
    ASSERT_EQ(runBake(dir, {"bake", sphere.string(), "-o", (dir / "s.slc").string(), "--backend",
                            "gpu", "--resolution", "8", "--quiet"})
                  .code,
              kExitOk);
    Result<format::ColliderAsset> parity = format::readAsset(dir / "s.slc");
    ASSERT_TRUE(parity.ok());
    EXPECT_FALSE(parity->meta.mesh.selfIntersecting);
    EXPECT_EQ(parity->meta.bake.signUsed, format::SignMethod::Parity);
}

TEST(CliGpuBake, ABadMeshIsReportedBeforeAMissingContext) {
    // The context opens while the mesh is read; the mesh's error still comes first (exit 2),
    // and a good mesh without a context is exit 3, as before.
    const fs::path dir = testmesh::tempDir("cli-gpu-order");
    const fs::path bad = dir / "bad.off";
    std::ofstream(bad) << "OFF\n3 1 0\n0 0 0\n1 0 0\n";
    const TimedRun badMesh =
        runBake(dir, {"bake", bad.string(), "-o", (dir / "x.slc").string(), "--backend", "gpu"},
                {"SLUICE_EGL_PLATFORM=nowhere"});
    EXPECT_EQ(badMesh.code, kExitBadInput) << shown(badMesh);
    EXPECT_NE(badMesh.err.find("bad.off"), std::string::npos) << badMesh.err;
    EXPECT_EQ(badMesh.err.find("NoGlContext"), std::string::npos) << badMesh.err;
    const TimedRun noContext = runBake(dir,
                                       {"bake", sphereMesh("cli-gpu-order").string(), "-o",
                                        (dir / "x.slc").string(), "--backend", "gpu"},
                                       {"SLUICE_EGL_PLATFORM=nowhere"});
    EXPECT_EQ(noContext.code, kExitNoGlContext) << shown(noContext);
    EXPECT_FALSE(fs::exists(dir / "x.slc"));
}

} // namespace
} // namespace sluice::bake
