// Atomic file replacement: success replaces whole, failure leaves the old file and no litter.
#include <algorithm>
#include <csignal>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "asset/AssetTestUtil.h"
#include "sluice/format/support/AtomicFile.h"
#include "support/TempDir.h"

namespace sluice::test {
namespace {

using namespace sluice::format;

std::vector<std::byte> bytesOf(const std::string& s) {
    const auto* p = reinterpret_cast<const std::byte*>(s.data());
    return {p, p + s.size()};
}

std::string contentOf(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(AtomicFile, CreatesANewFile) {
    TempDir dir;
    auto r = writeFileAtomic(dir / "out.bin", bytesOf("hello"));
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_EQ(contentOf(dir / "out.bin"), "hello");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}

TEST(AtomicFile, ReplacesAnExistingFileWhole) {
    TempDir dir;
    ASSERT_TRUE(writeFileAtomic(dir / "out.bin", bytesOf("a much longer old content")).ok());
    auto r = writeFileAtomic(dir / "out.bin", bytesOf("new"));
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_EQ(contentOf(dir / "out.bin"), "new");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}

TEST(AtomicFile, FailsWhenTheFolderIsMissing) {
    TempDir dir;
    auto r = writeFileAtomic(dir / "no-such-folder" / "out.bin", bytesOf("x"));
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::Io);
    EXPECT_NE(r.error().detail.find("no-such-folder"), std::string::npos) << r.error().detail;
    EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, FailsWhenTheTargetIsAFolderAndLeavesNoTemporaryFile) {
    TempDir dir;
    std::filesystem::create_directory(dir / "target");
    ASSERT_TRUE(writeFileAtomic(dir / "keep.bin", bytesOf("keep")).ok());
    auto r = writeFileAtomic(dir / "target", bytesOf("x"));
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::Io);
    EXPECT_TRUE(std::filesystem::is_directory(dir / "target"));
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"keep.bin", "target"}));
    EXPECT_EQ(contentOf(dir / "keep.bin"), "keep");
}

TEST(AtomicFile, KeepsThePreviousFileWhenTheWriteFailsMidway) {
    // A file-size limit makes write() fail with EFBIG after the temporary file exists and holds
    // part of the data: the failure this function exists for (disk full, quota).
    TempDir dir;
    const auto path = dir / "out.bin";
    ASSERT_TRUE(writeFileAtomic(path, bytesOf("previous")).ok());

    rlimit old{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit small = old;
    small.rlim_cur = 4096;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    const std::vector<std::byte> big(100000, std::byte{0x5A});
    auto r = writeFileAtomic(path, big);
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldHandler);

    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::Io);
    EXPECT_EQ(contentOf(path), "previous");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}

TEST(AtomicFile, FailsInAReadOnlyFolderAndKeepsThePreviousFile) {
    if (::geteuid() == 0)
        GTEST_SKIP() << "root ignores folder permissions; covered by the other failure tests";
    TempDir dir;
    const auto path = dir / "out.bin";
    ASSERT_TRUE(writeFileAtomic(path, bytesOf("previous")).ok());
    ::chmod(dir.path().c_str(), 0555);
    auto r = writeFileAtomic(path, bytesOf("new"));
    ::chmod(dir.path().c_str(), 0755);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::Io);
    EXPECT_EQ(contentOf(path), "previous");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}

TEST(AtomicFile, ConcurrentWritersLeaveOneWholeVersion) {
    TempDir dir;
    const auto path = dir / "out.bin";
    const std::vector<std::byte> a(50000, std::byte{'a'}), b(70000, std::byte{'b'});
    auto writer = [&](const std::vector<std::byte>& data) {
        for (int n = 0; n < 20; ++n)
            EXPECT_TRUE(writeFileAtomic(path, data).ok());
    };
    std::thread ta(writer, std::cref(a)), tb(writer, std::cref(b));
    ta.join();
    tb.join();
    const std::string content = contentOf(path);
    EXPECT_TRUE(content == std::string(50000, 'a') || content == std::string(70000, 'b'));
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}

/// The pid of a child that has exited and been reaped: it names no process now. 0 on failure.
pid_t reapedChild() {
    const pid_t child = ::fork();
    if (child == 0)
        ::_exit(0);
    if (child < 0 || ::waitpid(child, nullptr, 0) != child)
        return 0;
    return child;
}

TEST(AtomicFile, ASuccessfulWriteRemovesTheTemporaryFilesOfWritersNoLongerRunning) {
    // A writer killed between naming its complete file and the rename leaves
    // ".<name>.tmp-<pid>-...". The next write of that name removes it once its process is gone,
    // and leaves alone the files of running writers, of other names and of other patterns.
    TempDir dir;
    const pid_t child = reapedChild();
    ASSERT_GT(child, 0);
    const std::string dead = std::to_string(child), live = std::to_string(::getppid());
    const std::vector<std::string> kept = {".out.bin.tmp-" + live + "-0-7",   // still running
                                           ".other.bin.tmp-" + dead + "-0-7", // another file's
                                           ".out.bin.tmp-x" + dead + "-0-7",  // not a pid
                                           "out.bin.tmp-" + dead + "-0-7"};   // not hidden
    for (const std::string& name : kept)
        std::ofstream(dir / name) << "kept";
    std::ofstream(dir / (".out.bin.tmp-" + dead + "-3-12345")) << "left by a killed writer";
    std::ofstream(dir / "out.bin") << "previous";

    ASSERT_TRUE(writeFileAtomic(dir / "out.bin", bytesOf("new")).ok());
    std::vector<std::string> expected = kept;
    expected.push_back("out.bin");
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(dir.entries(), expected); // entries() is sorted
    EXPECT_EQ(contentOf(dir / "out.bin"), "new");
}

TEST(AtomicFile, AFailedWriteRemovesNothing) {
    TempDir dir;
    const pid_t child = reapedChild();
    ASSERT_GT(child, 0);
    const std::string stale = ".out.bin.tmp-" + std::to_string(child) + "-0-1";
    std::ofstream(dir / stale) << "left by a killed writer";
    std::filesystem::create_directory(dir / "out.bin"); // the target is a folder: the write fails
    EXPECT_FALSE(writeFileAtomic(dir / "out.bin", bytesOf("new")).ok());
    EXPECT_TRUE(std::filesystem::exists(dir / stale));
}

TEST(AtomicFile, ReadFileBytesReturnsTheWholeFile) {
    TempDir dir;
    ASSERT_TRUE(writeFileAtomic(dir / "f.bin", bytesOf("0123456789")).ok());
    auto r = readFileBytes(dir / "f.bin", 10);
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_EQ(*r, bytesOf("0123456789"));
}

TEST(AtomicFile, ReadFileBytesRefusesFilesOverTheLimitBeforeAllocating) {
    TempDir dir;
    ASSERT_TRUE(writeFileAtomic(dir / "f.bin", bytesOf("0123456789")).ok());
    auto r = readFileBytes(dir / "f.bin", 9);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::SizeOverflow);
}

TEST(AtomicFile, ReadFileBytesReportsMissingFilesAndFoldersAsIo) {
    TempDir dir;
    auto missing = readFileBytes(dir / "none", 100);
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::Io);
    auto folder = readFileBytes(dir.path(), 100);
    ASSERT_FALSE(folder.ok());
    EXPECT_EQ(folder.error().code, ErrorCode::Io);
}

} // namespace
} // namespace sluice::test
