// Buffer: round trips, offsets, clearing, allocation failures as values, moves and contracts.
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "sluice/gpu/Buffer.h"

namespace sluice::gpu {
namespace {

using BufferTest = test::GpuTest;

std::vector<std::uint32_t> pattern(std::size_t count, std::uint32_t seed) {
    std::vector<std::uint32_t> values(count);
    std::uint32_t state = seed;
    for (auto& value : values) {
        state = state * 1664525u + 1013904223u; // Numerical Recipes LCG
        value = state;
    }
    return values;
}

TEST_F(BufferTest, RoundTripsUploadedValues) {
    const auto values = pattern(10000, 7);
    auto buffer = Buffer::createFrom(values, "round trip");
    ASSERT_TRUE(buffer) << buffer.error().message();
    EXPECT_EQ(buffer->size(), values.size() * sizeof(std::uint32_t));
    EXPECT_NE(buffer->id(), 0u);
    EXPECT_EQ(buffer->download<std::uint32_t>(), values);
}

TEST_F(BufferTest, UploadsAndDownloadsAtAnOffset) {
    const auto base = pattern(256, 1);
    const auto patch = pattern(16, 2);
    auto buffer = Buffer::createFrom(base);
    ASSERT_TRUE(buffer);
    buffer->upload(patch, 100 * sizeof(std::uint32_t));

    std::vector<std::uint32_t> expected = base;
    std::copy(patch.begin(), patch.end(), expected.begin() + 100);
    EXPECT_EQ(buffer->download<std::uint32_t>(), expected);
    EXPECT_EQ(buffer->download<std::uint32_t>(100, 16), patch);
    EXPECT_EQ(buffer->download<std::uint32_t>(99, 1), std::vector<std::uint32_t>{base[99]});
}

TEST_F(BufferTest, ClearSetsEveryByteToZero) {
    const auto values = pattern(1001, 3);
    auto bytes = Buffer::create(4003); // not a multiple of 4
    ASSERT_TRUE(bytes);
    bytes->upload(values.data(), 4003);
    bytes->clear();
    std::vector<std::uint8_t> out(4003, 0xff);
    bytes->download(out.data(), out.size());
    EXPECT_EQ(out, std::vector<std::uint8_t>(4003, 0));
}

TEST_F(BufferTest, ReportsAnImpossibleAllocationAsGpuOutOfMemory) {
    // 16 TiB: more than any GPU (or llvmpipe's address space budget) holds.
    auto huge = Buffer::create(std::size_t{1} << 44, "huge");
    ASSERT_FALSE(huge);
    EXPECT_EQ(huge.error().code, ErrorCode::GpuOutOfMemory) << huge.error().message();
    EXPECT_NE(huge.error().detail.find("'huge'"), std::string::npos) << huge.error().detail;

    auto unrepresentable = Buffer::create(std::numeric_limits<std::size_t>::max());
    ASSERT_FALSE(unrepresentable);
    EXPECT_EQ(unrepresentable.error().code, ErrorCode::GpuOutOfMemory);

    // The context is still fine afterwards (TearDown also checks no debug error leaked).
    auto small = Buffer::createFrom(pattern(4, 9));
    ASSERT_TRUE(small) << small.error().message();
    EXPECT_EQ(small->download<std::uint32_t>(), pattern(4, 9));
}

TEST_F(BufferTest, RejectsAZeroSize) {
    auto empty = Buffer::create(0);
    ASSERT_FALSE(empty);
    EXPECT_EQ(empty.error().code, ErrorCode::InvalidArgument);
}

TEST_F(BufferTest, MoveTransfersOwnershipAndEmptiesTheSource) {
    auto created = Buffer::createFrom(pattern(8, 4));
    ASSERT_TRUE(created);
    Buffer source = std::move(*created);
    const GLuint id = source.id();
    Buffer target;
    target = std::move(source);
    EXPECT_EQ(target.id(), id);
    EXPECT_EQ(source.id(), 0u); // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(source.size(), 0u);
    EXPECT_EQ(target.download<std::uint32_t>(), pattern(8, 4));
}

TEST_F(BufferTest, TransfersOutsideTheBufferAreBrokenContracts) {
    auto buffer = Buffer::create(64);
    ASSERT_TRUE(buffer);
    std::vector<std::uint8_t> bytes(65);
    EXPECT_THROW(buffer->upload(bytes.data(), 65), std::runtime_error);
    EXPECT_THROW(buffer->upload(bytes.data(), 1, 64), std::runtime_error);
    EXPECT_THROW(buffer->download(bytes.data(), 8, 60), std::runtime_error);
    EXPECT_THROW((void)buffer->download<std::uint64_t>(8, 1), std::runtime_error);
    Buffer odd = Buffer::create(6).value();
    EXPECT_THROW((void)odd.download<std::uint32_t>(), std::runtime_error);
}

} // namespace
} // namespace sluice::gpu
