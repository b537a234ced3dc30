// Walks an untrusted NanoVDB float grid with bounds-checked copies, never through its pointers.
//
// Offsets and sizes come from NanoVDB.h's own structs (offsetof/sizeof), so the layout checked
// here is the one NanoVDB.h and PNanoVDB.h walk later. Every field is copied out with memcpy at
// an offset already known to lie inside the buffer; nothing is dereferenced in place.
#include "sluice/format/asset/NanoVdbCheck.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include <nanovdb/NanoVDB.h>

#include "asset/Bytes.h"

namespace sluice::format {

namespace {

namespace nv = nanovdb;
using GridData = nv::GridData;
using TreeData = nv::TreeData<3>;
using RootData = nv::NanoRoot<float>::DataType;
using RootTile = RootData::Tile;
using UpperData = nv::NanoUpper<float>::DataType;
using LowerData = nv::NanoLower<float>::DataType;
using LeafData = nv::NanoLeaf<float>::DataType;

static_assert(std::is_standard_layout_v<GridData> && std::is_standard_layout_v<TreeData> &&
                  std::is_standard_layout_v<RootData> && std::is_standard_layout_v<RootTile> &&
                  std::is_standard_layout_v<UpperData> && std::is_standard_layout_v<LowerData> &&
                  std::is_standard_layout_v<LeafData>,
              "offsetof needs standard-layout NanoVDB structs");
static_assert(sizeof(GridData) == 672 && sizeof(TreeData) == 64, "NanoVDB 32.x grid header");
static_assert(sizeof(RootTile::key) == 8, "NanoVDB built with USE_SINGLE_ROOT_KEY");

constexpr std::uint64_t kAlign = NANOVDB_DATA_ALIGNMENT;

using detail::checkedAdd;
using detail::checkedMul;

std::string str(std::uint64_t v) {
    return std::to_string(v);
}

/// One node array of the tree: `count` nodes of `stride` bytes from `begin` (buffer offset).
struct NodeArray {
    const char* what = "";
    std::uint64_t begin = 0;
    std::uint32_t count = 0;
    std::uint64_t stride = 0;
    std::vector<bool> reached;
    std::uint64_t end() const { return begin + std::uint64_t(count) * stride; }
};

class Walker {
public:
    Walker(std::span<const std::byte> bytes, std::string_view name)
        : m_bytes(bytes), m_name(name) {}

    Result<NanoVdbTreeStats> run();

private:
    template <class T> T at(std::uint64_t offset) const {
        T value;
        std::memcpy(&value, m_bytes.data() + offset, sizeof(T));
        return value;
    }
    Error bad(ErrorCode code, const std::string& what) const {
        return fail(code, m_name + ": NanoVDB grid: " + what);
    }

    Result<void> checkGridData();
    Result<void> checkTreeData();
    Result<void> checkRoot();
    Result<std::uint32_t> childIndex(std::uint64_t nodeOffset, std::int64_t childOffset,
                                     NodeArray& children);
    template <class NodeData>
    Result<void> checkInternal(std::uint64_t offset, NodeArray* children, const char* what);
    Result<void> checkLeaf(std::uint64_t offset);
    Result<void> checkFinite(float v, const std::string& where) const {
        if (!std::isfinite(v))
            return bad(ErrorCode::NonFinite, where + " is " + (std::isnan(v) ? "NaN" : "infinite"));
        return {};
    }

    std::span<const std::byte> m_bytes;
    std::string m_name;
    NanoVdbTreeStats m_stats;
    std::uint64_t m_tree = sizeof(GridData);
    std::uint64_t m_root = 0;
    std::uint32_t m_tableSize = 0;
    NodeArray m_leaves, m_lowers, m_uppers;
};

Result<void> Walker::checkGridData() {
    const std::uint64_t size = m_bytes.size();
    if (size < sizeof(GridData) + sizeof(TreeData))
        return bad(ErrorCode::Truncated, str(size) + " bytes, shorter than its " +
                                             str(sizeof(GridData) + sizeof(TreeData)) +
                                             "-byte grid and tree headers");
    if (at<std::uint64_t>(offsetof(GridData, mMagic)) != NANOVDB_MAGIC_NUMBER)
        return bad(ErrorCode::BadMagic, "wrong magic number (not a NanoVDB grid)");
    const auto version = at<std::uint32_t>(offsetof(GridData, mVersion));
    if ((version >> 21) != NANOVDB_MAJOR_VERSION_NUMBER)
        return bad(ErrorCode::UnsupportedVersion, "major version " + str(version >> 21) +
                                                      ", this build reads " +
                                                      str(NANOVDB_MAJOR_VERSION_NUMBER));
    if (at<std::uint32_t>(offsetof(GridData, mGridIndex)) != 0 ||
        at<std::uint32_t>(offsetof(GridData, mGridCount)) != 1)
        return bad(ErrorCode::Unsupported,
                   "not a single grid (index " +
                       str(at<std::uint32_t>(offsetof(GridData, mGridIndex))) + " of " +
                       str(at<std::uint32_t>(offsetof(GridData, mGridCount))) + ")");
    const auto gridSize = at<std::uint64_t>(offsetof(GridData, mGridSize));
    if (gridSize != size)
        return bad(gridSize > size ? ErrorCode::Truncated : ErrorCode::SizeMismatch,
                   "grid size " + str(gridSize) + " but the buffer holds " + str(size) + " bytes");
    if (size > kMaxNanoVdbBytes)
        return bad(ErrorCode::SizeOverflow,
                   str(size) + " bytes exceed the limit of " + str(kMaxNanoVdbBytes));
    if (at<nv::GridType>(offsetof(GridData, mGridType)) != nv::GridType::Float ||
        at<nv::GridClass>(offsetof(GridData, mGridClass)) != nv::GridClass::LevelSet)
        return bad(ErrorCode::Unsupported,
                   "not a float level set (grid type " +
                       str(std::uint32_t(at<nv::GridType>(offsetof(GridData, mGridType)))) +
                       ", class " +
                       str(std::uint32_t(at<nv::GridClass>(offsetof(GridData, mGridClass)))) + ")");
    if (at<std::uint32_t>(offsetof(GridData, mBlindMetadataCount)) != 0)
        return bad(ErrorCode::Unsupported, "blind data is not supported");

    // The map must be index -> world = voxelSize * ijk + translation (what bakes write).
    constexpr std::size_t map = offsetof(GridData, mMap);
    double mat[9], vec[3], voxel[3];
    std::memcpy(mat, m_bytes.data() + map + offsetof(nv::Map, mMatD), sizeof(mat));
    std::memcpy(vec, m_bytes.data() + map + offsetof(nv::Map, mVecD), sizeof(vec));
    std::memcpy(voxel, m_bytes.data() + offsetof(GridData, mVoxelSize), sizeof(voxel));
    for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(vec[a]) || !std::isfinite(voxel[a]))
            return bad(ErrorCode::NonFinite, "map translation or voxel size is not finite");
        if (!(voxel[a] > 0.0))
            return bad(ErrorCode::BadMetadata, "voxel size is not > 0");
        for (int b = 0; b < 3; ++b) {
            const double expect = a == b ? voxel[0] : 0.0;
            if (!std::isfinite(mat[3 * a + b]) ||
                std::abs(mat[3 * a + b] - expect) > 1e-9 * voxel[0])
                return bad(ErrorCode::BadMetadata,
                           "map is not a uniform scale by the voxel size plus a translation");
        }
    }
    m_stats.bytes = size;
    m_stats.voxelSize = {voxel[0], voxel[1], voxel[2]};
    m_stats.translation = {vec[0], vec[1], vec[2]};
    std::memcpy(m_stats.name.data(), m_bytes.data() + offsetof(GridData, mGridName),
                m_stats.name.size() - 1);
    return {};
}

Result<void> Walker::checkTreeData() {
    const std::uint64_t size = m_bytes.size();
    std::uint64_t offsets[4];
    std::uint32_t counts[3];
    std::memcpy(offsets, m_bytes.data() + m_tree + offsetof(TreeData, mNodeOffset),
                sizeof(offsets));
    std::memcpy(counts, m_bytes.data() + m_tree + offsetof(TreeData, mNodeCount), sizeof(counts));
    NodeArray* arrays[3] = {&m_leaves, &m_lowers, &m_uppers};
    const char* names[3] = {"leaf", "lower", "upper"};
    const std::uint64_t strides[3] = {sizeof(LeafData), sizeof(LowerData), sizeof(UpperData)};
    const std::uint64_t headers = m_tree + sizeof(TreeData);

    // [begin, end) of every section, to rule out overlaps.
    std::vector<std::pair<std::uint64_t, std::uint64_t>> sections;
    for (int level = 0; level < 3; ++level) {
        NodeArray& a = *arrays[level];
        a.what = names[level];
        a.count = counts[level];
        a.stride = strides[level];
        if (a.count == 0)
            continue;
        const auto begin = checkedAdd(m_tree, offsets[level]);
        const auto bytes = checkedMul(a.count, a.stride);
        const auto end = begin && bytes ? checkedAdd(*begin, *bytes) : std::nullopt;
        if (!bytes || *bytes > size)
            return bad(ErrorCode::SizeOverflow, str(a.count) + " " + a.what +
                                                    " nodes need more bytes than the grid's " +
                                                    str(size));
        if (!end || *begin < headers || *end > size || *begin % kAlign != 0)
            return bad(ErrorCode::OffsetOutOfRange, std::string(a.what) + " nodes at offset " +
                                                        str(offsets[level]) +
                                                        " lie outside the grid or are misaligned");
        a.begin = *begin;
        a.reached.assign(a.count, false);
        sections.emplace_back(*begin, *end);
    }

    const auto root = checkedAdd(m_tree, offsets[3]);
    if (!root || *root < headers || *root % kAlign != 0 ||
        *root > size - std::min<std::uint64_t>(size, sizeof(RootData)))
        return bad(ErrorCode::OffsetOutOfRange,
                   "root at offset " + str(offsets[3]) + " lies outside the grid or is misaligned");
    m_root = *root;
    m_tableSize = at<std::uint32_t>(m_root + offsetof(RootData, mTableSize));
    const std::uint64_t tableBytes = std::uint64_t(m_tableSize) * sizeof(RootTile); // < 2^38
    if (tableBytes > size - m_root - sizeof(RootData))
        return bad(ErrorCode::SizeOverflow,
                   "root table of " + str(m_tableSize) + " tiles runs past the end of the grid");
    sections.emplace_back(m_root, m_root + sizeof(RootData) + tableBytes);

    std::sort(sections.begin(), sections.end());
    for (std::size_t n = 1; n < sections.size(); ++n)
        if (sections[n].first < sections[n - 1].second)
            return bad(ErrorCode::OffsetOutOfRange, "node arrays overlap");
    return {};
}

// The node of `children` that a child offset (relative to its parent at `nodeOffset`) names.
Result<std::uint32_t> Walker::childIndex(std::uint64_t nodeOffset, std::int64_t childOffset,
                                         NodeArray& children) {
    // Two's complement add in 64 bits; anything outside the array fails the range check below.
    const std::uint64_t target = nodeOffset + std::uint64_t(childOffset);
    if (children.count == 0 || target < children.begin || target >= children.end() ||
        (target - children.begin) % children.stride != 0)
        return bad(ErrorCode::OffsetOutOfRange,
                   std::string("a child offset ") + std::to_string(childOffset) +
                       " does not land on one of the " + str(children.count) + " " + children.what +
                       " nodes");
    const auto index = std::uint32_t((target - children.begin) / children.stride);
    if (children.reached[index])
        return bad(ErrorCode::OffsetOutOfRange,
                   std::string(children.what) + " node " + str(index) +
                       " is the child of two parents (the tree must be a tree)");
    children.reached[index] = true;
    return index;
}

Result<void> Walker::checkRoot() {
    const float background = at<float>(m_root + offsetof(RootData, mBackground));
    if (auto ok = checkFinite(background, "the background"); !ok)
        return ok;
    m_stats.background = background;
    m_stats.rootTiles = m_tableSize;
    std::int32_t box[6];
    std::memcpy(box, m_bytes.data() + m_root + offsetof(RootData, mBBox), sizeof(box));
    m_stats.bboxMin = {box[0], box[1], box[2]};
    m_stats.bboxMax = {box[3], box[4], box[5]};

    for (std::uint32_t n = 0; n < m_tableSize; ++n) {
        const std::uint64_t tile = m_root + sizeof(RootData) + std::uint64_t(n) * sizeof(RootTile);
        const auto child = at<std::int64_t>(tile + offsetof(RootTile, child));
        if (child == 0) {
            ++m_stats.valueTiles;
            if (auto ok =
                    checkFinite(at<float>(tile + offsetof(RootTile, value)), "root tile " + str(n));
                !ok)
                return ok;
            continue;
        }
        auto index = childIndex(m_root, child, m_uppers);
        if (!index)
            return index.error();
        if (auto ok = checkInternal<UpperData>(m_uppers.begin + *index * m_uppers.stride, &m_lowers,
                                               "upper");
            !ok)
            return ok;
    }
    return {};
}

template <class NodeData>
Result<void> Walker::checkInternal(std::uint64_t offset, NodeArray* children, const char* what) {
    using Mask = decltype(NodeData::mChildMask);
    constexpr std::uint32_t kSize = std::uint32_t(sizeof(Mask) * 8);
    std::uint64_t words[kSize / 64];
    std::memcpy(words, m_bytes.data() + offset + offsetof(NodeData, mChildMask), sizeof(words));
    const std::uint64_t table = offset + offsetof(NodeData, mTable);
    for (std::uint32_t n = 0; n < kSize; ++n) {
        const std::uint64_t entry = table + std::uint64_t(n) * sizeof(typename NodeData::Tile);
        if (((words[n >> 6] >> (n & 63)) & 1u) == 0) {
            const float v = at<float>(entry);
            if (!std::isfinite(v))
                return checkFinite(v, std::string("a tile of an ") + what + " node");
            continue;
        }
        auto index = childIndex(offset, at<std::int64_t>(entry), *children);
        if (!index)
            return index.error();
        const std::uint64_t child = children->begin + *index * children->stride;
        auto ok = children == &m_lowers ? checkInternal<LowerData>(child, &m_leaves, "lower")
                                        : checkLeaf(child);
        if (!ok)
            return ok;
    }
    std::uint32_t childCount = 0;
    for (const std::uint64_t w : words)
        childCount += std::uint32_t(std::popcount(w));
    m_stats.valueTiles += kSize - childCount;
    return {};
}

Result<void> Walker::checkLeaf(std::uint64_t offset) {
    float values[512];
    std::memcpy(values, m_bytes.data() + offset + offsetof(LeafData, mValues), sizeof(values));
    for (const float v : values)
        if (!std::isfinite(v))
            return checkFinite(v, "a leaf value");
    std::uint64_t mask[8];
    std::memcpy(mask, m_bytes.data() + offset + offsetof(LeafData, mValueMask), sizeof(mask));
    for (const std::uint64_t w : mask)
        m_stats.activeVoxels += std::uint64_t(std::popcount(w));
    return {};
}

Result<NanoVdbTreeStats> Walker::run() {
    if (auto ok = checkGridData(); !ok)
        return ok.error();
    if (auto ok = checkTreeData(); !ok)
        return ok.error();
    if (auto ok = checkRoot(); !ok)
        return ok.error();
    for (const NodeArray* a : {&m_uppers, &m_lowers, &m_leaves})
        if (std::find(a->reached.begin(), a->reached.end(), false) != a->reached.end())
            return bad(ErrorCode::OffsetOutOfRange,
                       std::string("a ") + a->what + " node is not reached from the root");
    m_stats.leafNodes = m_leaves.count;
    m_stats.lowerNodes = m_lowers.count;
    m_stats.upperNodes = m_uppers.count;
    return m_stats;
}

} // namespace

Result<NanoVdbTreeStats> checkNanoVdbGrid(std::span<const std::byte> bytes,
                                          std::string_view nameForMessages) {
    return Walker(bytes, nameForMessages).run();
}

} // namespace sluice::format
