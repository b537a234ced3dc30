// Collider assets survive encode/decode and write/read: fp32 bit-exact, fp16 within its error.
#include <bit>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "asset/AssetTestUtil.h"
#include "support/TempDir.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/Half.h"

namespace sluice::test {
namespace {

using namespace sluice::format;

// Every metadata field except quantizationError, which the writer measures.
void expectSameMeta(const ColliderMeta& a, const ColliderMeta& b) {
    EXPECT_EQ(a.dims, b.dims);
    EXPECT_EQ(a.origin, b.origin);
    EXPECT_EQ(a.voxelSize, b.voxelSize);
    EXPECT_EQ(a.storage, b.storage);
    EXPECT_EQ(a.signConvention, b.signConvention);
    EXPECT_EQ(a.sourceFile, b.sourceFile);
    EXPECT_EQ(a.sourceHash, b.sourceHash);
    EXPECT_EQ(a.bake.backend, b.bake.backend);
    EXPECT_EQ(a.bake.resolution, b.bake.resolution);
    EXPECT_EQ(a.bake.padding, b.bake.padding);
    EXPECT_EQ(a.bake.signMode, b.bake.signMode);
    EXPECT_EQ(a.bake.signUsed, b.bake.signUsed);
    EXPECT_EQ(a.bake.scale, b.bake.scale);
    EXPECT_EQ(a.toolVersion, b.toolVersion);
    EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
    EXPECT_EQ(a.mesh.vertices, b.mesh.vertices);
    EXPECT_EQ(a.mesh.degenerateTriangles, b.mesh.degenerateTriangles);
    EXPECT_EQ(a.mesh.boundaryEdges, b.mesh.boundaryEdges);
    EXPECT_EQ(a.mesh.nonManifoldEdges, b.mesh.nonManifoldEdges);
    EXPECT_EQ(a.mesh.closed, b.mesh.closed);
    EXPECT_EQ(a.mesh.selfIntersecting, b.mesh.selfIntersecting);
    EXPECT_EQ(a.validation.known, b.validation.known);
    EXPECT_EQ(a.validation.pointsChecked, b.validation.pointsChecked);
    EXPECT_EQ(a.validation.maxError, b.validation.maxError);
    EXPECT_EQ(a.validation.meanError, b.validation.meanError);
    EXPECT_EQ(a.validation.rmsError, b.validation.rmsError);
    EXPECT_EQ(a.validation.signMismatches, b.validation.signMismatches);
    EXPECT_EQ(a.validation.eikonalMedian, b.validation.eikonalMedian);
    EXPECT_EQ(a.validation.eikonalP99, b.validation.eikonalP99);
    EXPECT_EQ(a.validation.eikonalOutsideShare, b.validation.eikonalOutsideShare);
    ASSERT_EQ(a.meshMass.has_value(), b.meshMass.has_value());
    if (a.meshMass) {
        EXPECT_EQ(a.meshMass->volume, b.meshMass->volume);
        EXPECT_EQ(a.meshMass->centerOfMass, b.meshMass->centerOfMass);
        EXPECT_EQ(a.meshMass->inertia, b.meshMass->inertia);
    }
}

// Half an fp16 ulp at |x| [same units as x]: the round-to-nearest bound for one sample.
double halfUlpBound(float x) {
    const double a = std::abs(double(x));
    if (a < std::ldexp(1.0, -14))
        return std::ldexp(1.0, -25); // subnormal spacing 2^-24
    return std::ldexp(1.0, std::ilogb(a) - 11);
}

TEST(AssetRoundTrip, Fp32IsBitExactWithEveryMetadataField) {
    ColliderAsset asset = makeAsset({4, 3, 5}, Storage::F32);
    // Awkward but finite floats: signed zero, a subnormal, extremes of the range.
    asset.distances[0] = -0.0f;
    asset.distances[1] = std::numeric_limits<float>::denorm_min();
    asset.distances[2] = std::numeric_limits<float>::max();
    asset.distances[3] = std::numeric_limits<float>::lowest();
    asset.meta.quantizationError = 123.0; // ignored by the writer: fp32 stores exactly

    auto encoded = encodeAsset(asset);
    ASSERT_TRUE(encoded.ok()) << encoded.error().message();
    EXPECT_EQ(encoded->quantizationError, 0.0);
    auto decoded = decodeAsset(encoded->bytes, "roundtrip.sdf");
    ASSERT_TRUE(decoded.ok()) << decoded.error().message();

    expectSameMeta(asset.meta, decoded->meta);
    EXPECT_EQ(decoded->meta.quantizationError, 0.0);
    ASSERT_EQ(decoded->distances.size(), asset.distances.size());
    for (std::size_t n = 0; n < asset.distances.size(); ++n)
        EXPECT_EQ(std::bit_cast<std::uint32_t>(decoded->distances[n]),
                  std::bit_cast<std::uint32_t>(asset.distances[n]))
            << "sample " << n;
}

TEST(AssetRoundTrip, Fp16StaysWithinTheRecordedQuantizationError) {
    ColliderAsset asset = makeAsset({7, 6, 5}, Storage::F16);
    double bound = 0.0;
    for (const float d : asset.distances)
        bound = std::max(bound, halfUlpBound(d));

    auto encoded = encodeAsset(asset);
    ASSERT_TRUE(encoded.ok()) << encoded.error().message();
    const double q = encoded->quantizationError;
    EXPECT_GT(q, 0.0);
    EXPECT_LE(q, bound);

    auto decoded = decodeAsset(encoded->bytes, "half.sdf");
    ASSERT_TRUE(decoded.ok()) << decoded.error().message();
    expectSameMeta(asset.meta, decoded->meta);
    EXPECT_EQ(decoded->meta.quantizationError, q);
    double worst = 0.0;
    for (std::size_t n = 0; n < asset.distances.size(); ++n) {
        const double err = std::abs(double(decoded->distances[n]) - double(asset.distances[n]));
        EXPECT_LE(err, halfUlpBound(asset.distances[n])) << "sample " << n;
        worst = std::max(worst, err);
    }
    EXPECT_EQ(worst, q); // the recorded figure is the measured maximum, not a bound
    // Half the bytes of fp32 in the payload.
    EXPECT_EQ(headerOf(encoded->bytes).payloadSize, asset.pointCount() * 2);
}

TEST(AssetRoundTrip, ReencodingAnFp16AssetKeepsItsRecordedQuantizationError) {
    // Samples read back from fp16 are exact halves; a re-write (validate --write) must not
    // measure them afresh as error-free and lose the figure from the original bake.
    ColliderAsset asset = makeAsset({7, 6, 5}, Storage::F16);
    auto first = encodeAsset(asset);
    ASSERT_TRUE(first.ok()) << first.error().message();
    ASSERT_GT(first->quantizationError, 0.0);
    auto decoded = decodeAsset(first->bytes, "half.slc");
    ASSERT_TRUE(decoded.ok()) << decoded.error().message();
    auto second = encodeAsset(*decoded);
    ASSERT_TRUE(second.ok()) << second.error().message();
    EXPECT_EQ(second->quantizationError, first->quantizationError);
    EXPECT_EQ(second->bytes, first->bytes);
}

TEST(AssetRoundTrip, Fp16ClampsDistancesBeyondTheHalfRangeAndRecordsTheError) {
    ColliderAsset asset = makeAsset({2, 2, 2}, Storage::F16);
    asset.distances[0] = 1.0e5f;
    asset.distances[1] = -7.0e4f;
    auto encoded = encodeAsset(asset);
    ASSERT_TRUE(encoded.ok()) << encoded.error().message();
    EXPECT_DOUBLE_EQ(encoded->quantizationError, 1.0e5 - 65504.0);
    auto decoded = decodeAsset(encoded->bytes, "clamp.sdf");
    ASSERT_TRUE(decoded.ok()) << decoded.error().message();
    EXPECT_EQ(decoded->distances[0], kHalfMax);
    EXPECT_EQ(decoded->distances[1], -kHalfMax);
}

TEST(AssetRoundTrip, WriteThenReadGivesTheSameAsset) {
    TempDir dir;
    const ColliderAsset asset = makeAsset({5, 4, 3}, Storage::F32);
    const auto path = dir / "collider.sdf";
    auto written = writeAsset(path, asset);
    ASSERT_TRUE(written.ok()) << written.error().message();
    auto read = readAsset(path);
    ASSERT_TRUE(read.ok()) << read.error().message();
    expectSameMeta(asset.meta, read->meta);
    EXPECT_EQ(read->distances, asset.distances);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"collider.sdf"});
}

TEST(AssetRoundTrip, EncodingTwiceGivesIdenticalBytes) {
    const ColliderAsset asset = makeAsset({6, 5, 4}, Storage::F16);
    EXPECT_EQ(encodeOk(asset), encodeOk(asset));
}

TEST(AssetRoundTrip, PayloadStartsAlignedAndSamplesAreLittleEndianXFastest) {
    ColliderAsset asset = makeAsset({3, 2, 2}, Storage::F32);
    for (std::size_t n = 0; n < asset.distances.size(); ++n)
        asset.distances[n] = float(n) + 0.5f;
    const auto bytes = encodeOk(asset);
    const AssetHeader h = headerOf(bytes);
    EXPECT_EQ(h.payloadOffset % kAssetPayloadAlignment, 0u);
    EXPECT_EQ(h.metaOffset, kAssetHeaderSize);
    EXPECT_EQ(h.fileSize, bytes.size());
    // Sample (i, j, k) = (1, 1, 1) is number 1 + 3 * (1 + 2 * 1) = 10: 10.5f = 0x41280000.
    const std::size_t at = h.payloadOffset + 10 * 4;
    EXPECT_EQ(std::to_integer<int>(bytes[at + 0]), 0x00);
    EXPECT_EQ(std::to_integer<int>(bytes[at + 2]), 0x28);
    EXPECT_EQ(std::to_integer<int>(bytes[at + 3]), 0x41);
    // dims sit at their documented metadata offset.
    EXPECT_EQ(peek<std::uint32_t>(bytes, metaAt(bytes, meta_offset::kDims)), 3u);
    EXPECT_EQ(peek<double>(bytes, metaAt(bytes, meta_offset::kVoxelSize)), 0.125);
}

TEST(AssetWriter, RejectsNaNAndInfiniteSamples) {
    ColliderAsset asset = makeAsset();
    asset.distances[5] = std::numeric_limits<float>::quiet_NaN();
    auto nan = encodeAsset(asset);
    ASSERT_FALSE(nan.ok());
    EXPECT_EQ(nan.error().code, ErrorCode::NonFinite);
    asset.distances[5] = std::numeric_limits<float>::infinity();
    auto inf = encodeAsset(asset);
    ASSERT_FALSE(inf.ok());
    EXPECT_EQ(inf.error().code, ErrorCode::NonFinite);
}

TEST(AssetWriter, RejectsZeroOrSingleDims) {
    ColliderAsset asset = makeAsset();
    asset.meta.dims = {0, 4, 5};
    asset.distances.clear();
    auto zero = encodeAsset(asset);
    ASSERT_FALSE(zero.ok());
    EXPECT_EQ(zero.error().code, ErrorCode::InvalidArgument);
    asset.meta.dims = {1, 4, 5};
    asset.distances.assign(20, 1.0f);
    auto one = encodeAsset(asset);
    ASSERT_FALSE(one.ok());
    EXPECT_EQ(one.error().code, ErrorCode::InvalidArgument);
}

TEST(AssetWriter, RejectsInconsistentOrOutOfRangeMetadata) {
    auto codeOf = [](const ColliderAsset& a) {
        auto r = encodeAsset(a);
        return r.ok() ? std::optional<ErrorCode>{} : std::optional(r.error().code);
    };
    ColliderAsset a = makeAsset();
    a.distances.pop_back();
    EXPECT_EQ(codeOf(a), ErrorCode::InvalidArgument);

    a = makeAsset();
    a.meta.voxelSize = 0.0;
    EXPECT_EQ(codeOf(a), ErrorCode::InvalidArgument);
    a.meta.voxelSize = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(codeOf(a), ErrorCode::NonFinite);

    a.meta.voxelSize = 1.0e308; // finite, but the far corner is not
    EXPECT_EQ(codeOf(a), ErrorCode::NonFinite);

    a = makeAsset();
    a.meta.origin.y = std::numeric_limits<double>::infinity();
    EXPECT_EQ(codeOf(a), ErrorCode::NonFinite);

    a = makeAsset();
    a.meta.storage = Storage(9);
    EXPECT_EQ(codeOf(a), ErrorCode::InvalidArgument);

    a = makeAsset();
    a.meta.sourceFile.assign(kAssetMaxStringBytes + 1, 'x');
    EXPECT_EQ(codeOf(a), ErrorCode::InvalidArgument);

    // Too many points is refused from dims alone, before looking at (or allocating) samples.
    a = makeAsset();
    a.meta.dims = {1024, 1024, 512};
    a.distances.clear();
    EXPECT_EQ(codeOf(a), ErrorCode::SizeOverflow);
}

TEST(AssetWriter, FailedEncodeLeavesThePreviousFileInPlace) {
    TempDir dir;
    const auto path = dir / "collider.sdf";
    const ColliderAsset good = makeAsset();
    ASSERT_TRUE(writeAsset(path, good).ok());
    ColliderAsset bad = makeAsset({3, 3, 3});
    bad.distances[0] = std::numeric_limits<float>::quiet_NaN();
    auto r = writeAsset(path, bad);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::NonFinite);
    EXPECT_NE(r.error().detail.find("collider.sdf"), std::string::npos) << r.error().detail;
    auto read = readAsset(path);
    ASSERT_TRUE(read.ok()) << read.error().message();
    EXPECT_EQ(read->distances, good.distances);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"collider.sdf"});
}

} // namespace
} // namespace sluice::test
