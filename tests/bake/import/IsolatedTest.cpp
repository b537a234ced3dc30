// The isolated importer: answers cross the pipe exactly; crashes, hangs and throws become errors.
#include <atomic>
#include <bit>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <oneapi/tbb/parallel_for.h>
#include <unistd.h>

#include "TestMeshes.h"
#include "sluice/bake/import/Isolated.h"
#include "sluice/bake/import/MeshImport.h"

using namespace sluice;
using namespace sluice::bake;
using namespace std::chrono_literals;

namespace {

IsolationLimits quick() {
    IsolationLimits limits;
    limits.timeout = 20s;
    return limits;
}

/// The threads of process `pid`, from /proc.
std::size_t threadsOf(pid_t pid) {
    const std::filesystem::path tasks = "/proc/" + std::to_string(pid) + "/task";
    return std::size_t(std::distance(std::filesystem::directory_iterator(tasks),
                                     std::filesystem::directory_iterator()));
}

} // namespace

TEST(Isolated, ReturnsTheChildsSoupBitForBit) {
    TriangleSoup soup;
    soup.positions = {{0.1, -2.5e-300, 1e300}, {-0.0, 3.0, 7.25}, {1.0 / 3.0, 2.0, -4.0}};
    soup.triangles = {{0, 1, 2}, {2, 1, 0}};
    Result<TriangleSoup> got = runIsolated("soup", quick(), [&] { return Result(soup); });
    ASSERT_TRUE(got.ok()) << got.error().message();
    ASSERT_EQ(got->positions.size(), soup.positions.size());
    for (std::size_t i = 0; i < soup.positions.size(); ++i)
        for (int a = 0; a < 3; ++a)
            EXPECT_EQ(std::bit_cast<std::uint64_t>(got->positions[i][a]),
                      std::bit_cast<std::uint64_t>(soup.positions[i][a]));
    EXPECT_EQ(got->triangles, soup.triangles);
}

TEST(Isolated, ForksFromAProcessWhoseLibraryThreadsHaveStopped) {
    // A thread running at the fork may hold the allocator's lock, and the child then hangs in
    // its first allocation (CI: a validate of a .vdb, whose reader had started TBB's workers).
    if (std::thread::hardware_concurrency() < 2)
        GTEST_SKIP() << "one CPU: TBB starts no worker thread to stop";
    std::atomic<long> sum{0};
    tbb::parallel_for(0, 1 << 16, [&](int i) { sum += i; });
    ASSERT_GT(threadsOf(::getpid()), 1u) << "TBB kept no worker: nothing here to stop";
    const pid_t parent = ::getpid();
    Result<TriangleSoup> got = runIsolated("threads", quick(), [parent] {
        TriangleSoup soup; // one position per thread the parent has while this child runs
        soup.positions.resize(threadsOf(parent));
        return Result(soup);
    });
    ASSERT_TRUE(got.ok()) << got.error().message();
    EXPECT_EQ(got->positions.size(), 1u);
    // TBB works again afterwards, with workers of its own.
    tbb::parallel_for(0, 1 << 16, [&](int i) { sum -= i; });
    EXPECT_EQ(sum.load(), 0);
}

TEST(Isolated, CarriesASoupLargerThanAPipeBuffer) {
    // 200k triangles is about 5 MB on the wire, far beyond the 64 KiB a pipe holds.
    TriangleSoup soup;
    for (std::uint32_t i = 0; i < 200'000; ++i) {
        soup.positions.push_back({double(i), double(i) * 0.5, -double(i)});
        soup.triangles.push_back({i, (i + 1) % 200'000, (i + 2) % 200'000});
    }
    Result<TriangleSoup> got = runIsolated("big", quick(), [&] { return Result(soup); });
    ASSERT_TRUE(got.ok()) << got.error().message();
    EXPECT_EQ(got->positions, soup.positions);
    EXPECT_EQ(got->triangles, soup.triangles);
}

TEST(Isolated, PassesTheChildsErrorThroughWithItsCode) {
    Result<TriangleSoup> got = runIsolated("file.obj", quick(), []() -> Result<TriangleSoup> {
        return fail(ErrorCode::NonFinite, "file.obj: vertex 3 is NaN");
    });
    ASSERT_FALSE(got.ok());
    EXPECT_EQ(got.error().code, ErrorCode::NonFinite);
    EXPECT_EQ(got.error().detail, "file.obj: vertex 3 is NaN");
}

TEST(Isolated, AnAbortInTheChildIsAMeshImportErrorNamingTheFile) {
    Result<TriangleSoup> got =
        runIsolated("hostile.fbx", quick(), []() -> Result<TriangleSoup> { std::abort(); });
    ASSERT_FALSE(got.ok());
    EXPECT_EQ(got.error().code, ErrorCode::MeshImport);
    EXPECT_NE(got.error().detail.find("hostile.fbx"), std::string::npos) << got.error().detail;
    EXPECT_NE(got.error().detail.find("SIGABRT"), std::string::npos) << got.error().detail;
}

TEST(Isolated, ASegmentationFaultInTheChildIsAMeshImportError) {
    Result<TriangleSoup> got = runIsolated("crash.obj", quick(), []() -> Result<TriangleSoup> {
        std::raise(SIGSEGV);
        return TriangleSoup{};
    });
    ASSERT_FALSE(got.ok());
    EXPECT_EQ(got.error().code, ErrorCode::MeshImport);
#if defined(__SANITIZE_ADDRESS__)
    // AddressSanitizer catches the signal itself, reports, and exits with status 1.
    EXPECT_NE(got.error().detail.find("without an answer"), std::string::npos)
        << got.error().detail;
#else
    EXPECT_NE(got.error().detail.find("SIGSEGV"), std::string::npos) << got.error().detail;
#endif
}

TEST(Isolated, AnExceptionInTheChildIsAnError) {
    Result<TriangleSoup> got = runIsolated("throw.obj", quick(), []() -> Result<TriangleSoup> {
        throw std::runtime_error("parser gave up");
    });
    ASSERT_FALSE(got.ok());
    EXPECT_EQ(got.error().code, ErrorCode::MeshImport);
    EXPECT_NE(got.error().detail.find("parser gave up"), std::string::npos);
}

TEST(Isolated, AHangIsStoppedAtTheTimeout) {
    IsolationLimits limits;
    limits.timeout = 300ms;
    const auto start = std::chrono::steady_clock::now();
    Result<TriangleSoup> got = runIsolated("slow.dae", limits, []() -> Result<TriangleSoup> {
        std::this_thread::sleep_for(60s);
        return TriangleSoup{};
    });
    const auto took = std::chrono::steady_clock::now() - start;
    ASSERT_FALSE(got.ok());
    EXPECT_EQ(got.error().code, ErrorCode::MeshImport);
    EXPECT_NE(got.error().detail.find("did not finish"), std::string::npos) << got.error().detail;
    EXPECT_LT(took, 10s); // stopped near the 0.3 s limit, not after the child's 60 s
}

TEST(Isolated, TheMemoryCapTurnsARunawayAllocationIntoAnError) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the address-space cap is off under AddressSanitizer";
#else
    IsolationLimits limits = quick();
    limits.maxAddressSpaceBytes = std::uint64_t(2) << 30;
    Result<TriangleSoup> got = runIsolated("bomb.off", limits, []() -> Result<TriangleSoup> {
        std::vector<char> huge(std::size_t(8) << 30, 1); // 8 GiB, over the 2 GiB cap
        return TriangleSoup{};
    });
    ASSERT_FALSE(got.ok());
    EXPECT_EQ(got.error().code, ErrorCode::SizeOverflow) << got.error().message();
#endif
}

TEST(Isolated, ImportGivesTheSameMeshInAndOutOfTheChild) {
    const auto path = testmesh::writeTempObj(testmesh::torusSoup({0.0, 0.0, 0.0}, 1.0, 0.3, 24, 12),
                                             "isolated", "torus.obj");
    ASSERT_FALSE(path.empty());
    ImportOptions inChild;
    ImportOptions inProcess;
    inProcess.isolate = false;
    Result<ImportedMesh> a = importMesh(path, inChild);
    Result<ImportedMesh> b = importMesh(path, inProcess);
    ASSERT_TRUE(a.ok()) << a.error().message();
    ASSERT_TRUE(b.ok()) << b.error().message();
    EXPECT_EQ(a->soup.positions, b->soup.positions);
    EXPECT_EQ(a->soup.triangles, b->soup.triangles);
    EXPECT_EQ(a->sourceHash, b->sourceHash);
    EXPECT_EQ(a->diagnostics.triangles, 24u * 12u * 2u);
}
