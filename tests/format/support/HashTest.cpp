// XXH3-64 against values from the reference tool, hex formatting, and streamed file hashes.
#include <string_view>

#include <gtest/gtest.h>

#include "asset/AssetTestUtil.h"
#include "support/TempDir.h"
#include "sluice/format/support/AtomicFile.h"
#include "sluice/format/support/Hash.h"

namespace sluice::test {
namespace {

using namespace sluice::format;

std::span<const std::byte> bytesOf(std::string_view s) {
    return std::as_bytes(std::span(s));
}

// Deterministic test data: byte n = (n * mul + add) % mod.
std::vector<std::byte> pattern(std::size_t size, unsigned mul, unsigned add, unsigned mod) {
    std::vector<std::byte> out(size);
    for (std::size_t n = 0; n < size; ++n)
        out[n] = std::byte((n * mul + add) % mod);
    return out;
}

// Expected values computed with `xxhsum -H3` (xxhsum 0.8.1, Debian package `xxhash`), e.g.
// `printf 'sluice' | xxhsum -H3`; the patterns were written to files by a Python one-liner.
constexpr std::uint64_t kXxh3Empty = 0x2d06800538d394c2ull;
constexpr std::uint64_t kXxh3Sluice = 0x7e13095f1588691dull;
constexpr std::uint64_t kXxh3Pattern1000 = 0x989765d0ea7a5ecdull; // (n*31+7) % 256, 1000 B
constexpr std::uint64_t kXxh3Pattern200k = 0x0fbb8b4955feb894ull; // (n*131+17) % 251, 200000 B

TEST(Hash, MatchesTheReferenceToolOnKnownInputs) {
    EXPECT_EQ(xxh3(bytesOf("")), kXxh3Empty);
    EXPECT_EQ(xxh3(bytesOf("sluice")), kXxh3Sluice);
    EXPECT_EQ(xxh3(pattern(1000, 31, 7, 256)), kXxh3Pattern1000);
    EXPECT_EQ(xxh3(pattern(200000, 131, 17, 251)), kXxh3Pattern200k);
}

TEST(Hash, Hex64IsSixteenLowercaseDigits) {
    EXPECT_EQ(hex64(0), "0000000000000000");
    EXPECT_EQ(hex64(0xABC), "0000000000000abc");
    EXPECT_EQ(hex64(kXxh3Sluice), "7e13095f1588691d");
    EXPECT_EQ(hex64(~0ull), "ffffffffffffffff");
}

TEST(Hash, FileHashStreamsAndMatchesTheReferenceTool) {
    TempDir dir;
    // 200000 bytes spans several read chunks.
    ASSERT_TRUE(writeFileAtomic(dir / "p.bin", pattern(200000, 131, 17, 251)).ok());
    ASSERT_TRUE(writeFileAtomic(dir / "s.txt", bytesOf("sluice")).ok());
    ASSERT_TRUE(writeFileAtomic(dir / "empty", {}).ok());
    auto p = hashFileHex(dir / "p.bin");
    ASSERT_TRUE(p.ok()) << p.error().message();
    EXPECT_EQ(*p, "0fbb8b4955feb894");
    auto s = hashFileHex(dir / "s.txt");
    ASSERT_TRUE(s.ok()) << s.error().message();
    EXPECT_EQ(*s, "7e13095f1588691d");
    auto e = hashFileHex(dir / "empty");
    ASSERT_TRUE(e.ok()) << e.error().message();
    EXPECT_EQ(*e, hex64(kXxh3Empty));
}

TEST(Hash, FileHashReportsMissingFilesAndFoldersAsIo) {
    TempDir dir;
    auto missing = hashFileHex(dir / "missing.obj");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::Io);
    EXPECT_NE(missing.error().detail.find("missing.obj"), std::string::npos);
    auto folder = hashFileHex(dir.path());
    ASSERT_FALSE(folder.ok());
    EXPECT_EQ(folder.error().code, ErrorCode::Io);
}

} // namespace
} // namespace sluice::test
