// Volume maps baked with a collider (format 1.3): they survive encode/decode, dense and sparse,
// a baked map is found for a support within the tolerance only, and every way a file or an
// asset can hold a bad map is refused with a message naming it.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "asset/AssetTestUtil.h"
#include "asset/SparseTestUtil.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/GridSamples.h"

namespace sluice::test {
namespace {

using namespace sluice::format;

// A map of `points` values that differ from point to point and from map to map.
VolumeMap rampMap(double support, std::uint64_t points) {
    VolumeMap map;
    map.support = support;
    for (std::uint64_t n = 0; n < points; ++n)
        map.values.push_back(float(std::sin(double(n) + 10.0 * support)) * 0.25f);
    return map;
}

ColliderAsset withMaps(ColliderAsset asset, std::initializer_list<double> supports) {
    for (double s : supports)
        asset.volumeMaps.push_back(rampMap(s, volumeMapPoints(asset)));
    return asset;
}

void expectSameMaps(const ColliderAsset& a, const ColliderAsset& b) {
    ASSERT_EQ(a.volumeMaps.size(), b.volumeMaps.size());
    for (std::size_t m = 0; m < a.volumeMaps.size(); ++m) {
        EXPECT_EQ(a.volumeMaps[m].support, b.volumeMaps[m].support);
        EXPECT_EQ(a.volumeMaps[m].values, b.volumeMaps[m].values) << "map " << m;
    }
}

std::string decodeMessage(std::span<const std::byte> bytes) {
    auto r = decodeAsset(bytes, "maps.slc");
    return r ? std::string("accepted") : r.error().message();
}

TEST(VolumeMapAsset, DenseAndSparseMapsRoundTripBitExactAfterTheirSamples) {
    const ColliderAsset dense = withMaps(makeAsset({3, 4, 5}), {0.04, 0.1});
    auto read = decodeAsset(encodeOk(dense), "dense.slc");
    ASSERT_TRUE(read) << read.error().message();
    EXPECT_EQ(read->distances, dense.distances);
    expectSameMaps(*read, dense);
    EXPECT_EQ(headerOf(encodeOk(dense)).minor, kAssetMinor);

    const ColliderAsset sparse = withMaps(makeSparseSphere(), {0.2});
    ASSERT_EQ(volumeMapPoints(sparse), 512ull * sparseLeafCount(sparse));
    read = decodeAsset(encodeOk(sparse), "sparse.slc");
    ASSERT_TRUE(read) << read.error().message();
    EXPECT_EQ(read->grid, sparse.grid);
    expectSameMaps(*read, sparse);

    // f16 samples of 3 x 4 x 5 take 120 bytes: the first map starts at 128, after zeros.
    const ColliderAsset half = withMaps(makeAsset({3, 4, 5}, Storage::F16), {0.04});
    const std::vector<std::byte> halfBytes = encodeOk(half);
    EXPECT_EQ(payloadOf(halfBytes).size(), 128u + 240u);
    for (std::size_t b = 120; b < 128; ++b)
        EXPECT_EQ(payloadOf(halfBytes)[b], std::byte{0}) << "padding byte " << b;
    read = decodeAsset(halfBytes, "half.slc");
    ASSERT_TRUE(read) << read.error().message();
    expectSameMaps(*read, half);

    // Without maps the payload is the samples alone, as before 1.3.
    const std::vector<std::byte> plain = encodeOk(makeAsset({3, 4, 5}));
    EXPECT_EQ(payloadOf(plain).size(), 3u * 4u * 5u * 4u);
    // With maps each starts on a 16-byte boundary after the samples: 240 bytes, then two maps
    // of 60 values padded to 240.
    EXPECT_EQ(payloadOf(encodeOk(dense)).size(), 240u + 240u + 240u);
}

TEST(VolumeMapAsset, AMapIsFoundForItsSupportWithinTheTolerance) {
    const ColliderAsset a = withMaps(makeAsset(), {0.04, 0.0266667});
    ASSERT_NE(a.volumeMapFor(0.04), nullptr);
    EXPECT_EQ(a.volumeMapFor(0.04)->support, 0.04);
    EXPECT_EQ(a.volumeMapFor(double(0.04f))->support, 0.04); // the scene's float h
    EXPECT_EQ(a.volumeMapFor(double(0.04f) / double(1.5f))->support, 0.0266667);
    EXPECT_EQ(a.volumeMapFor(0.0401), nullptr); // 0.25 % off
    EXPECT_EQ(a.volumeMapFor(0.06), nullptr);
}

TEST(VolumeMapAsset, TheWriterRefusesMapsTheReaderWouldReject) {
    const auto refused = [](const ColliderAsset& a, const std::string& words) {
        auto r = encodeAsset(a);
        ASSERT_FALSE(r) << words;
        EXPECT_NE(r.error().message().find(words), std::string::npos) << r.error().message();
    };
    ColliderAsset a = withMaps(makeAsset(), {0.04});
    a.volumeMaps[0].values.pop_back();
    refused(a, "volume map 0 has 59 values for 60 points");
    a = withMaps(makeAsset(), {0.04, 0.040001});
    refused(a, "volume maps 0 and 1 have the same support");
    a = withMaps(makeAsset(), {0.0});
    refused(a, "volume map 0 has support");
    a = withMaps(makeAsset(), {0.04});
    a.volumeMaps[0].values[7] = std::numeric_limits<float>::quiet_NaN();
    refused(a, "volume map 0 point 7 is not finite");
    a = withMaps(makeAsset(), {0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.09});
    refused(a, "9 volume maps, more than 8");
}

TEST(VolumeMapAsset, TheReaderRejectsBadMapsNamingThem) {
    const ColliderAsset a = withMaps(makeAsset({3, 4, 5}), {0.04});
    const std::vector<std::byte> good = encodeOk(a);
    const std::span<const std::byte> payload = payloadOf(good);
    const std::size_t mapAt = headerOf(good).payloadOffset + 240;

    // A non-finite value, the file resealed (so only the value is wrong).
    std::vector<std::byte> bytes = good;
    poke(bytes, mapAt + 4 * 5, std::numeric_limits<float>::infinity());
    reseal(bytes);
    EXPECT_EQ(decodeError(bytes), ErrorCode::NonFinite);
    EXPECT_NE(decodeMessage(bytes).find("volume map 0 point 5 is infinite"), std::string::npos)
        << decodeMessage(bytes);

    // A payload one map short of what the metadata says: a size mismatch.
    const std::vector<std::byte> shortPayload(payload.begin(), payload.begin() + 240);
    bytes = assemble(metaOf(good), shortPayload);
    EXPECT_EQ(decodeError(bytes), ErrorCode::SizeMismatch);
    EXPECT_NE(decodeMessage(bytes).find("1 volume maps of 60 points need"), std::string::npos)
        << decodeMessage(bytes);

    // The support, the last 8 bytes of the metadata, made 0, then NaN.
    const std::span<const std::byte> meta = metaOf(good);
    for (double support : {0.0, std::nan("")}) {
        std::vector<std::byte> m(meta.begin(), meta.end());
        std::memcpy(m.data() + m.size() - 8, &support, 8);
        bytes = assemble(m, payload);
        EXPECT_EQ(decodeError(bytes), ErrorCode::BadMetadata);
        EXPECT_NE(decodeMessage(bytes).find("volume map 0 has support"), std::string::npos)
            << decodeMessage(bytes);
    }

    // A map count past the limit, in the u32 before the supports.
    std::vector<std::byte> m(meta.begin(), meta.end());
    const std::uint32_t many = 9;
    std::memcpy(m.data() + m.size() - 12, &many, 4);
    bytes = assemble(m, payload);
    EXPECT_EQ(decodeError(bytes), ErrorCode::BadMetadata);
    EXPECT_NE(decodeMessage(bytes).find("volume map count 9 exceeds the limit of 8"),
              std::string::npos)
        << decodeMessage(bytes);

    // The samples' size larger than the payload.
    m.assign(meta.begin(), meta.end());
    const std::uint64_t huge = payload.size() + 16;
    std::memcpy(m.data() + m.size() - 20, &huge, 8);
    bytes = assemble(m, payload);
    EXPECT_EQ(decodeError(bytes), ErrorCode::SizeMismatch);
}

} // namespace
} // namespace sluice::test
