// Sparse (NanoVDB) collider assets: round trip, sampling, and hostile grid buffers.
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "asset/AssetTestUtil.h"
#include "asset/SparseTestUtil.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/NanoVdbCheck.h"
#include "sluice/format/asset/SdfSampler.h"

namespace sluice::test {
namespace {

using namespace sluice::format;
namespace ho = header_offset;

using RootData = nanovdb::NanoRoot<float>::DataType;

ErrorCode gridError(const ColliderAsset& a) {
    auto r = checkNanoVdbGrid(a.grid, "grid.nvdb");
    if (r.ok()) {
        ADD_FAILURE() << "checkNanoVdbGrid accepted a grid it should reject";
        return ErrorCode::Io;
    }
    EXPECT_EQ(r.error().detail.rfind("grid.nvdb: ", 0), 0u) << r.error().detail;
    return r.error().code;
}

/// A file that passes every container check but carries `a`'s (possibly hostile) grid.
std::vector<std::byte> fileWithGrid(const ColliderAsset& a) {
    const auto good = encodeOk(makeSparseSphere());
    // The metadata's samples' size (1.3: a u64, then the u32 map count, last) says the grid's.
    std::vector<std::byte> meta(metaOf(good).begin(), metaOf(good).end());
    const std::uint64_t samples = a.grid.size();
    std::memcpy(meta.data() + meta.size() - 12, &samples, sizeof samples);
    return assemble(meta, std::span(a.grid.data(), a.grid.size()));
}

/// The same field as a dense asset: every grid point read from the sparse tree.
ColliderAsset denseCopy(const ColliderAsset& sparse) {
    ColliderAsset d;
    d.meta = sparse.meta;
    d.meta.layout = Layout::Dense;
    d.meta.bandWidth = 0.0;
    d.distances.resize(d.pointCount());
    const auto& tree = nanoGrid(sparse).tree();
    for (std::uint32_t k = 0; k < d.meta.dims.z; ++k)
        for (std::uint32_t j = 0; j < d.meta.dims.y; ++j)
            for (std::uint32_t i = 0; i < d.meta.dims.x; ++i)
                d.distances[d.index(i, j, k)] =
                    tree.getValue(nanovdb::Coord(int(i), int(j), int(k)));
    return d;
}

TEST(SparseAsset, RoundTripsItsGridBytesAndMetadata) {
    const ColliderAsset a = makeSparseSphere();
    ASSERT_TRUE(checkNanoVdbGrid(a.grid, "sphere").ok());
    const auto bytes = encodeOk(a);
    EXPECT_EQ(headerOf(bytes).minor, kAssetMinor);
    auto r = decodeAsset(bytes, "sparse.slc");
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_TRUE(r->sparse());
    EXPECT_EQ(r->meta.bandWidth, 3.0);
    EXPECT_EQ(r->meta.dims, a.meta.dims);
    EXPECT_TRUE(r->distances.empty());
    ASSERT_EQ(r->grid.size(), a.grid.size());
    EXPECT_EQ(std::memcmp(r->grid.data(), a.grid.data(), a.grid.size()), 0);
    EXPECT_EQ(encodeOk(*r), bytes) << "re-encoding gives the same bytes";
}

TEST(SparseAsset, KeepsTheMeshMassPropertiesBesideItsGrid) {
    // A sparse bake of a closed mesh records its mass properties as a dense one does.
    ColliderAsset a = makeSparseSphere();
    MassProperties mass;
    mass.volume = 4.0 / 3.0 * std::numbers::pi * 0.125;
    mass.centerOfMass = {0.1, -0.2, 0.3};
    mass.inertia = glm::dmat3(0.4 * mass.volume * 0.25);
    a.meta.meshMass = mass;
    auto r = decodeAsset(encodeOk(a), "sparse-mass.slc");
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_TRUE(r->sparse());
    ASSERT_TRUE(r->meta.meshMass.has_value());
    EXPECT_EQ(r->meta.meshMass->volume, mass.volume);
    EXPECT_EQ(r->meta.meshMass->centerOfMass, mass.centerOfMass);
    EXPECT_EQ(r->meta.meshMass->inertia, mass.inertia);
}

TEST(SparseAsset, CountsTheTreeItWalks) {
    const ColliderAsset a = makeSparseSphere();
    auto stats = checkNanoVdbGrid(a.grid, "sphere");
    ASSERT_TRUE(stats.ok()) << stats.error().message();
    const auto& tree = nanoGrid(a).tree();
    EXPECT_EQ(stats->leafNodes, tree.nodeCount(0));
    EXPECT_EQ(stats->lowerNodes, tree.nodeCount(1));
    EXPECT_EQ(stats->upperNodes, tree.nodeCount(2));
    EXPECT_EQ(stats->activeVoxels, tree.activeVoxelCount());
    EXPECT_GT(stats->activeVoxels, 1000u);
    EXPECT_FLOAT_EQ(stats->background, float(3.0 * 0.05));
    EXPECT_EQ(stats->bytes, a.grid.size());
}

TEST(SparseAsset, SamplesLikeTheDenseGridOfTheSameValues) {
    const ColliderAsset sparse = makeSparseSphere();
    const ColliderAsset dense = denseCopy(sparse);
    const SdfSampler s(sparse), d(dense);
    std::mt19937 rng(7);
    const glm::dvec3 lo = sparse.meta.origin - glm::dvec3(0.2);
    const glm::dvec3 hi = s.boxMax() + glm::dvec3(0.2);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int n = 0; n < 20000; ++n) {
        const glm::dvec3 p = lo + (hi - lo) * glm::dvec3(u(rng), u(rng), u(rng));
        ASSERT_EQ(s.value(p), d.value(p)) << "at " << p.x << " " << p.y << " " << p.z;
        const glm::dvec3 gs = s.gradient(p), gd = d.gradient(p);
        ASSERT_EQ(gs, gd);
    }
}

TEST(SparseAsset, IsExactNearTheSurfaceNegativeDeepInsideAndPositiveOutside) {
    const double r = 0.5, h = 0.05;
    const glm::dvec3 c{0.1, -0.2, 0.3};
    const ColliderAsset a = makeSparseSphere(r, h, 3.0, c);
    const SdfSampler s(a);
    EXPECT_FLOAT_EQ(s.value(c), float(-3.0 * h)) << "deep inside reads the negative background";
    EXPECT_LT(s.value(c + glm::dvec3(0.2, 0.1, 0.0)), 0.0f);
    EXPECT_GT(s.value(c + glm::dvec3(0.7, 0.0, 0.0)), 0.0f);
    EXPECT_GT(s.value(c + glm::dvec3(5.0, 0.0, 0.0)), 4.0f) << "outside the box: farther, larger";
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int checked = 0;
    for (int n = 0; n < 5000; ++n) {
        const glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
        const double t = u(rng) * h; // within one voxel of the surface
        const glm::dvec3 p = c + dir * (r + t);
        EXPECT_NEAR(s.value(p), t, 0.05 * h);
        EXPECT_GT(glm::dot(s.gradient(p), dir), 0.9);
        ++checked;
    }
    EXPECT_EQ(checked, 5000);
}

TEST(SparseAsset, LoadsACommittedVersion10DenseFile) {
    std::ifstream in(std::string(SLUICE_SOURCE_DIR) + "/tests/format/data/asset-v1.0.slc",
                     std::ios::binary);
    const std::vector<char> raw{std::istreambuf_iterator<char>(in),
                                std::istreambuf_iterator<char>()};
    ASSERT_FALSE(raw.empty());
    const auto* p = reinterpret_cast<const std::byte*>(raw.data());
    const std::vector<std::byte> bytes(p, p + raw.size());
    EXPECT_EQ(headerOf(bytes).minor, 0);
    auto r = decodeAsset(bytes, "asset-v1.0.slc");
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_EQ(r->meta.layout, Layout::Dense);
    EXPECT_EQ(r->meta.bandWidth, 0.0);
    const ColliderAsset expected = makeAsset({3, 4, 5});
    EXPECT_EQ(r->distances, expected.distances);
    EXPECT_EQ(r->meta.sourceFile, expected.meta.sourceFile);
    // Written again it becomes a current (1.2) file with the same field.
    auto again = decodeAsset(encodeOk(*r), "again.slc");
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again->distances, expected.distances);
}

TEST(SparseAsset, AnOlderMinorHeaderOverA12BodyIsBadMetadata) {
    // 1.0 and 1.1 have no layout field: read as either, a sparse body has bytes left over.
    for (std::uint16_t minor = 0; minor < kAssetMinorSparse; ++minor) {
        auto bytes = encodeOk(makeSparseSphere());
        poke<std::uint16_t>(bytes, ho::kMinor, minor);
        EXPECT_EQ(decodeError(bytes), ErrorCode::BadMetadata) << "minor " << minor;
    }
}

TEST(SparseAsset, TheWriterRefusesWhatTheReaderRejects) {
    ColliderAsset a = makeSparseSphere();
    a.meta.bandWidth = 0.0;
    EXPECT_EQ(encodeAsset(a).error().code, ErrorCode::InvalidArgument);
    a = makeSparseSphere();
    a.meta.origin.x += 0.01;
    EXPECT_EQ(encodeAsset(a).error().code, ErrorCode::InvalidArgument);
    a = makeSparseSphere();
    a.grid.resize(a.grid.size() - 32);
    EXPECT_FALSE(encodeAsset(a).ok());
    a = makeSparseSphere();
    a.meta.storage = Storage::F16;
    EXPECT_EQ(encodeAsset(a).error().code, ErrorCode::InvalidArgument);
}

TEST(SparseAsset, RejectsEveryTruncatedGrid) {
    const ColliderAsset a = makeSparseSphere();
    for (std::size_t len = 0; len < a.grid.size(); len += (len < 2048 ? 1 : 997)) {
        auto r = checkNanoVdbGrid(std::span(a.grid.data(), len), "grid.nvdb");
        ASSERT_FALSE(r.ok()) << "prefix of " << len;
        EXPECT_EQ(r.error().code, ErrorCode::Truncated) << "prefix of " << len;
    }
}

TEST(SparseAsset, RejectsABadMagicAnotherMajorAndAnotherValueType) {
    ColliderAsset a = makeSparseSphere();
    pokeGrid<std::uint64_t>(a, offsetof(nanovdb::GridData, mMagic), 0x1234);
    EXPECT_EQ(gridError(a), ErrorCode::BadMagic);
    a = makeSparseSphere();
    pokeGrid<std::uint32_t>(a, offsetof(nanovdb::GridData, mVersion), 31u << 21);
    EXPECT_EQ(gridError(a), ErrorCode::UnsupportedVersion);
    a = makeSparseSphere();
    pokeGrid(a, offsetof(nanovdb::GridData, mGridType), nanovdb::GridType::Double);
    EXPECT_EQ(gridError(a), ErrorCode::Unsupported);
    a = makeSparseSphere();
    pokeGrid<std::uint64_t>(a, offsetof(nanovdb::GridData, mGridSize), a.grid.size() + 32);
    EXPECT_EQ(gridError(a), ErrorCode::Truncated);
}

TEST(SparseAsset, RejectsNodeOffsetsOutOfRangeAndHugeCounts) {
    constexpr std::size_t tree = sizeof(nanovdb::GridData);
    constexpr std::size_t offsets = tree + offsetof(nanovdb::TreeData<3>, mNodeOffset);
    constexpr std::size_t counts = tree + offsetof(nanovdb::TreeData<3>, mNodeCount);
    for (int level = 0; level < 4; ++level) {
        for (const std::uint64_t off : {std::uint64_t(1) << 40, ~std::uint64_t(0) - 31,
                                        std::uint64_t(0), std::uint64_t(32)}) {
            ColliderAsset a = makeSparseSphere();
            pokeGrid<std::uint64_t>(a, offsets + 8 * level, off);
            EXPECT_EQ(gridError(a), ErrorCode::OffsetOutOfRange) << "level " << level;
        }
    }
    for (int level = 0; level < 3; ++level) {
        ColliderAsset a = makeSparseSphere();
        pokeGrid<std::uint32_t>(a, counts + 4 * level, 0xFFFFFFFFu);
        EXPECT_EQ(gridError(a), ErrorCode::SizeOverflow) << "level " << level;
    }
    ColliderAsset a = makeSparseSphere();
    const std::size_t root = gridOffset(a, &nanoGrid(a).tree().root());
    pokeGrid<std::uint32_t>(a, root + offsetof(RootData, mTableSize), 0x7FFFFFFFu);
    EXPECT_EQ(gridError(a), ErrorCode::SizeOverflow);
}

TEST(SparseAsset, RejectsCyclesSharedChildrenAndUnreachedNodes) {
    using UpperData = nanovdb::NanoUpper<float>::DataType;
    using LowerData = nanovdb::NanoLower<float>::DataType;
    const ColliderAsset good = makeSparseSphere();
    const auto& tree = nanoGrid(good).tree();
    const auto* upper = tree.getFirstNode<2>();
    const auto* lower = tree.getFirstNode<1>();
    auto firstOn = [](const auto& mask, std::uint32_t from) {
        while (from < mask.bitCount() && !mask.isOn(from))
            ++from;
        return from;
    };
    const std::uint32_t un = firstOn(upper->childMask(), 0);
    const std::uint32_t ln = firstOn(lower->childMask(), 0);
    const std::uint32_t ln2 = firstOn(lower->childMask(), ln + 1);
    ASSERT_LT(ln2, 4096u);
    const std::size_t upperAt = gridOffset(good, upper);
    const std::size_t lowerAt = gridOffset(good, lower);
    const std::size_t rootAt = gridOffset(good, &tree.root());

    ColliderAsset a = good; // an upper node's child is the upper node itself
    pokeGrid<std::int64_t>(a, upperAt + offsetof(UpperData, mTable) + 8 * un, 0);
    EXPECT_EQ(gridError(a), ErrorCode::OffsetOutOfRange);
    a = good; // a lower node's child is the root
    pokeGrid<std::int64_t>(a, lowerAt + offsetof(LowerData, mTable) + 8 * ln,
                           std::int64_t(rootAt) - std::int64_t(lowerAt));
    EXPECT_EQ(gridError(a), ErrorCode::OffsetOutOfRange);
    a = good; // two entries name the same leaf
    std::int64_t first = 0;
    std::memcpy(&first, a.grid.data() + lowerAt + offsetof(LowerData, mTable) + 8 * ln, 8);
    pokeGrid<std::int64_t>(a, lowerAt + offsetof(LowerData, mTable) + 8 * ln2, first);
    EXPECT_EQ(gridError(a), ErrorCode::OffsetOutOfRange);
    a = good; // a child offset between two leaves
    pokeGrid<std::int64_t>(a, lowerAt + offsetof(LowerData, mTable) + 8 * ln, first + 4);
    EXPECT_EQ(gridError(a), ErrorCode::OffsetOutOfRange);
}

TEST(SparseAsset, RejectsNonFiniteValuesAnywhereALookupCanReachThem) {
    const ColliderAsset good = makeSparseSphere();
    const auto& tree = nanoGrid(good).tree();
    const std::size_t leafAt = gridOffset(good, tree.getFirstNode<0>());
    const std::size_t rootAt = gridOffset(good, &tree.root());
    for (const float bad : {std::nanf(""), INFINITY, -INFINITY}) {
        ColliderAsset a = good;
        pokeGrid(a, leafAt + offsetof(nanovdb::NanoLeaf<float>::DataType, mValues) + 4 * 100, bad);
        EXPECT_EQ(gridError(a), ErrorCode::NonFinite);
        a = good;
        pokeGrid(a, rootAt + offsetof(RootData, mBackground), bad);
        EXPECT_EQ(gridError(a), ErrorCode::NonFinite);
    }
}

TEST(SparseAsset, HostileGridsInsideAnAssetFileAreRejectedByTheReader) {
    ColliderAsset a = makeSparseSphere();
    const std::size_t counts =
        sizeof(nanovdb::GridData) + offsetof(nanovdb::TreeData<3>, mNodeCount);
    pokeGrid<std::uint32_t>(a, counts, 0xFFFFFFFFu);
    EXPECT_EQ(decodeError(fileWithGrid(a)), ErrorCode::SizeOverflow);
    a = makeSparseSphere();
    a.grid.resize(a.grid.size() - 64);
    EXPECT_EQ(decodeError(fileWithGrid(a)), ErrorCode::Truncated);
    EXPECT_TRUE(decodeAsset(fileWithGrid(makeSparseSphere()), "ok.slc").ok());
}

TEST(SparseAsset, RandomByteFlipsAreRejectedOrSampleFinitely) {
    const ColliderAsset good = makeSparseSphere(0.3, 0.05);
    std::mt19937 rng(11);
    std::uniform_int_distribution<std::size_t> at(0, good.grid.size() - 1);
    std::uniform_int_distribution<int> bit(0, 7);
    int accepted = 0;
    for (int n = 0; n < 3000; ++n) {
        ColliderAsset a = good;
        for (int f = 0; f < 4; ++f)
            a.grid[at(rng)] ^= std::byte(1u << bit(rng));
        if (!checkNanoVdbGrid(a.grid, "flip").ok())
            continue;
        ++accepted;
        const SdfSampler s(a);
        for (double t = 0.0; t <= 1.0; t += 0.125)
            ASSERT_TRUE(std::isfinite(s.value(a.meta.origin + (s.boxMax() - a.meta.origin) * t)));
    }
    EXPECT_GT(accepted, 0) << "flips in values and statistics leave valid grids";
}

} // namespace
} // namespace sluice::test
