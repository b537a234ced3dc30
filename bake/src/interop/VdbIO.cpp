// OpenVDB interchange: collider assets out as float level sets, level sets in as meshes.
#include "sluice/bake/interop/VdbIO.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <ios>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <glm/common.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include "interop/VdbFileCheck.h"
#include "interop/VdbHeaders.h"
#include "interop/VdbMesh.h"
#include "interop/VdbWrite.h"
#include "sluice/bake/Grid.h"
#include "sluice/format/support/Hash.h"

namespace fs = std::filesystem;

namespace sluice::bake {
namespace {

using detail::quoted;
using FloatLeaf = openvdb::FloatTree::LeafNodeType;

constexpr const char* kGridName = "sdf";
// Grid metadata keys; prefixed so they never collide with OpenVDB's own (class, name, creator).
constexpr const char* kMetaSourceFile = "sluice_source_file";
constexpr const char* kMetaSourceHash = "sluice_source_hash";
constexpr const char* kMetaToolVersion = "sluice_tool_version";
constexpr const char* kMetaBackend = "sluice_bake_backend";
constexpr const char* kMetaSignMethod = "sluice_sign_method";
constexpr const char* kMetaExporter = "sluice_exported_by";

// Archive::readHeader compares the first 8 bytes, OPENVDB_MAGIC as a little-endian int64.
constexpr std::array<unsigned char, 8> kVdbMagic{0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0};

Result<void> checkExportable(const format::ColliderAsset& asset) {
    const format::ColliderMeta& meta = asset.meta;
    if (meta.dims.x == 0 || meta.dims.y == 0 || meta.dims.z == 0)
        return fail(ErrorCode::InvalidArgument, "cannot export an asset with an empty grid");
    // OpenVDB coordinates are int32.
    constexpr std::uint32_t kMaxDim = std::uint32_t(std::numeric_limits<std::int32_t>::max()) - 8;
    if (meta.dims.x > kMaxDim || meta.dims.y > kMaxDim || meta.dims.z > kMaxDim)
        return fail(ErrorCode::SizeOverflow, "grid dimensions exceed OpenVDB's coordinate range");
    if (asset.distances.size() != asset.pointCount())
        return fail(ErrorCode::InvalidArgument,
                    "asset holds " + std::to_string(asset.distances.size()) + " distances for " +
                        std::to_string(asset.pointCount()) + " grid points");
    if (!std::isfinite(meta.voxelSize) || meta.voxelSize <= 0.0)
        return fail(ErrorCode::InvalidArgument, "voxel size must be finite and > 0");
    if (!std::isfinite(meta.origin.x) || !std::isfinite(meta.origin.y) ||
        !std::isfinite(meta.origin.z))
        return fail(ErrorCode::NonFinite, "grid origin is not finite");
    for (float d : asset.distances)
        if (!std::isfinite(d))
            return fail(ErrorCode::NonFinite, "asset holds a non-finite distance");
    return {};
}

// Builds leaf nodes directly (in parallel) rather than through an accessor: every grid point
// becomes an active voxel, even where it equals the background, so the dense grid survives.
void setProvenance(openvdb::FloatGrid& grid, const format::ColliderMeta& meta);

openvdb::FloatGrid::Ptr buildGrid(const format::ColliderAsset& asset) {
    const format::ColliderMeta& meta = asset.meta;
    float background = 0.0f;
    for (float d : asset.distances)
        background = std::max(background, std::abs(d));

    auto grid = openvdb::FloatGrid::create(background);
    constexpr std::uint32_t kLeafDim = FloatLeaf::DIM;
    const glm::uvec3 leafCount = (meta.dims + (kLeafDim - 1)) / kLeafDim;
    std::vector<std::unique_ptr<FloatLeaf>> leaves(std::size_t(leafCount.x) * leafCount.y *
                                                   leafCount.z);
    // 128 leaves (64 K points) per task at least: small grids stay on this thread.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, leaves.size(), 128), [&](const auto& range) {
            for (std::size_t n = range.begin(); n != range.end(); ++n) {
                const glm::uvec3 lo(std::uint32_t(n % leafCount.x) * kLeafDim,
                                    std::uint32_t(n / leafCount.x % leafCount.y) * kLeafDim,
                                    std::uint32_t(n / (std::size_t(leafCount.x) * leafCount.y)) *
                                        kLeafDim);
                const glm::uvec3 hi = glm::min(lo + kLeafDim, meta.dims);
                auto leaf = std::make_unique<FloatLeaf>(
                    openvdb::Coord(int(lo.x), int(lo.y), int(lo.z)), background, false);
                for (std::uint32_t k = lo.z; k < hi.z; ++k)
                    for (std::uint32_t j = lo.y; j < hi.y; ++j)
                        for (std::uint32_t i = lo.x; i < hi.x; ++i)
                            leaf->setValueOn(
                                FloatLeaf::coordToOffset(openvdb::Coord(int(i), int(j), int(k))),
                                asset.distances[asset.index(i, j, k)]);
                leaves[n] = std::move(leaf);
            }
        });
    for (auto& leaf : leaves)
        grid->tree().addLeaf(leaf.release());

    // Index (i, j, k) maps to origin + (i, j, k) * voxelSize.
    auto transform = openvdb::math::Transform::createLinearTransform(meta.voxelSize);
    transform->postTranslate(openvdb::Vec3d(meta.origin.x, meta.origin.y, meta.origin.z));
    grid->setTransform(transform);
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setName(kGridName);
    setProvenance(*grid, meta);
    return grid;
}

// Provenance in grid metadata, read back by readVdbDense.
void setProvenance(openvdb::FloatGrid& grid, const format::ColliderMeta& meta) {
    const std::string exporter = std::string("sluice-bake ") + SLUICE_VERSION;
    grid.setCreator(meta.toolVersion.empty() ? exporter : meta.toolVersion);
    grid.insertMeta(kMetaSourceFile, openvdb::StringMetadata(meta.sourceFile));
    grid.insertMeta(kMetaSourceHash, openvdb::StringMetadata(meta.sourceHash));
    grid.insertMeta(kMetaToolVersion, openvdb::StringMetadata(meta.toolVersion));
    grid.insertMeta(kMetaBackend, openvdb::StringMetadata(meta.bake.backend));
    grid.insertMeta(kMetaSignMethod,
                    openvdb::StringMetadata(format::signMethodName(meta.bake.signUsed)));
    grid.insertMeta(kMetaExporter, openvdb::StringMetadata(exporter));
}

// fsync of a file or (for a rename to last) its folder.
bool syncPath(const fs::path& path, bool folder) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (folder ? O_DIRECTORY : 0));
    if (fd < 0)
        return false;
    const bool ok = ::fsync(fd) == 0;
    ::close(fd);
    return ok;
}

} // namespace

// OpenVDB writes through its own ofstream, so the temp-and-rename is done here rather than
// through format's byte-span writer.
Result<void> detail::writeVdbAtomically(const openvdb::GridCPtrVec& grids, const fs::path& path) {
    const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        return fail(ErrorCode::Io, "cannot write " + quoted(path) + ": folder " + quoted(folder) +
                                       " does not exist");
    if (path.filename().empty() || fs::is_directory(path, ec))
        return fail(ErrorCode::Io, "cannot write " + quoted(path) + ": it is a folder");

    static std::atomic<unsigned> counter{0};
    const fs::path temp = folder / ("." + path.filename().string() + ".tmp" +
                                    std::to_string(::getpid()) + "-" + std::to_string(counter++));
    try {
        openvdb::io::File file(temp.string());
        file.write(grids);
        file.close();
    } catch (const std::exception& e) {
        fs::remove(temp, ec);
        return fail(ErrorCode::Io, "cannot write " + quoted(path) + ": " + e.what());
    }
    // Archive::write does not report short writes (disk full): walk what landed on disk, and
    // make it durable before it replaces anything.
    if (auto complete = detail::checkVdbExtents(temp); !complete || !syncPath(temp, false)) {
        fs::remove(temp, ec);
        return fail(ErrorCode::Io, "cannot write " + quoted(path) +
                                       ": the file on disk is incomplete (disk full?)");
    }
    fs::rename(temp, path, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(temp, ignored);
        return fail(ErrorCode::Io,
                    "cannot rename the temporary file to " + quoted(path) + ": " + ec.message());
    }
    syncPath(folder, true); // the rename itself; best effort, as in format::writeFileAtomic
    return {};
}

namespace {

// Checks the magic first, so "not a VDB" and "a cut-off VDB" get different codes.
Result<void> checkMagic(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec))
        return fail(ErrorCode::Io, "cannot open " + quoted(path) + ": no such file");
    if (!fs::is_regular_file(path, ec))
        return fail(ErrorCode::Io, "cannot open " + quoted(path) + ": not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return fail(ErrorCode::Io, "cannot open " + quoted(path) + " for reading");
    std::array<unsigned char, kVdbMagic.size()> head{};
    in.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
    const auto got = std::size_t(in.gcount());
    if (got == 0)
        return fail(ErrorCode::MeshImport, quoted(path) + " is empty, not a VDB file");
    if (std::memcmp(head.data(), kVdbMagic.data(), got) != 0)
        return fail(ErrorCode::MeshImport,
                    quoted(path) + " is not an OpenVDB file (no VDB magic number)");
    if (got < kVdbMagic.size())
        return fail(ErrorCode::Truncated, quoted(path) + " is truncated: " + std::to_string(got) +
                                              " bytes, shorter than a VDB header");
    return {};
}

// Reads every grid through io::Stream on a stream that throws on a short read: OpenVDB does not
// check its reads, and a cut-off file would otherwise be parsed from garbage. checkVdbExtents
// catches cut-off files first; the throwing stream covers files it cannot walk.
Result<openvdb::GridPtrVecPtr> readAllGrids(const fs::path& path) {
    if (auto magic = checkMagic(path); !magic)
        return magic.error();
    if (auto extents = detail::checkVdbExtents(path); !extents)
        return extents.error();
    initOpenVdb();
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return fail(ErrorCode::Io, "cannot open " + quoted(path) + " for reading");
    in.exceptions(std::ios::failbit | std::ios::badbit);
    try {
        openvdb::io::Stream stream(in, /*delayLoad=*/false);
        openvdb::GridPtrVecPtr grids = stream.getGrids();
        if (!grids)
            grids = std::make_shared<openvdb::GridPtrVec>();
        return grids;
    } catch (const std::ios_base::failure&) {
        if (in.eof())
            return fail(ErrorCode::Truncated,
                        quoted(path) + " is truncated: the VDB data ends early; export it again");
        return fail(ErrorCode::Io, "cannot read " + quoted(path));
    } catch (const std::bad_alloc&) {
        return fail(ErrorCode::MeshImport,
                    "cannot read " + quoted(path) + ": corrupt VDB (implausible sizes)");
    } catch (const std::exception& e) {
        return fail(ErrorCode::MeshImport, "cannot read " + quoted(path) + ": " + e.what());
    }
}

// The first float level set, else the first float grid (with a warning on stderr).
Result<openvdb::FloatGrid::Ptr> loadFloatGrid(const fs::path& path) {
    auto grids = readAllGrids(path);
    if (!grids)
        return grids.error();
    openvdb::FloatGrid::Ptr firstFloat;
    for (const openvdb::GridBase::Ptr& base : **grids) {
        auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        if (!grid)
            continue;
        if (grid->getGridClass() == openvdb::GRID_LEVEL_SET)
            return grid;
        if (!firstFloat)
            firstFloat = grid;
    }
    if (!firstFloat) {
        std::string types;
        for (const openvdb::GridBase::Ptr& base : **grids)
            types += (types.empty() ? "" : ", ") + base->getName() + " (" + base->type() + ")";
        return fail(ErrorCode::Unsupported, quoted(path) + " has no float grid to read" +
                                                (types.empty() ? std::string(" (it holds no grids)")
                                                               : " (it holds " + types + ")") +
                                                "; save the level set as a FloatGrid");
    }
    std::fprintf(stderr,
                 "warning: %s: grid '%s' is a float grid of class '%s', not a level set; "
                 "reading it as one\n",
                 path.string().c_str(), firstFloat->getName().c_str(),
                 openvdb::GridBase::gridClassToString(firstFloat->getGridClass()).c_str());
    return firstFloat;
}

std::string stringMeta(const openvdb::GridBase& grid, const char* key) {
    if (auto value = grid.getMetadata<openvdb::StringMetadata>(key))
        return value->value();
    return {};
}

format::SignMethod signMethodFromName(const std::string& name) {
    if (name == "parity")
        return format::SignMethod::Parity;
    if (name == "winding")
        return format::SignMethod::Winding;
    return format::SignMethod::Level;
}

} // namespace

Result<void> exportVdb(const format::ColliderAsset& asset, const fs::path& path) {
    if (asset.sparse()) {
        // The narrow band as it is: active band voxels, tiles and background as stored.
        initOpenVdb();
        openvdb::FloatGrid::Ptr grid;
        try {
            grid = detail::sparseToOpenVdb(asset);
            setProvenance(*grid, asset.meta);
        } catch (const std::exception& e) {
            return fail(ErrorCode::Io,
                        "cannot build the VDB grid for " + quoted(path) + ": " + e.what());
        }
        return detail::writeVdbAtomically(openvdb::GridCPtrVec{grid}, path);
    }
    if (auto ok = checkExportable(asset); !ok)
        return fail(ok.error().code, "cannot export to " + quoted(path) + ": " + ok.error().detail);
    initOpenVdb();
    openvdb::FloatGrid::Ptr grid;
    try {
        grid = buildGrid(asset);
    } catch (const std::exception& e) {
        return fail(ErrorCode::Io,
                    "cannot build the VDB grid for " + quoted(path) + ": " + e.what());
    }
    return detail::writeVdbAtomically(openvdb::GridCPtrVec{grid}, path);
}

Result<ImportedMesh> importVdbLevelSet(const fs::path& path, double scale) {
    if (!std::isfinite(scale) || scale <= 0.0)
        return fail(ErrorCode::InvalidArgument, "scale must be finite and > 0");
    auto loaded = loadFloatGrid(path);
    if (!loaded)
        return loaded.error();
    return detail::meshLevelSet(**loaded, path, scale);
}

Result<format::ColliderAsset> readVdbDense(const fs::path& path) {
    auto loaded = loadFloatGrid(path);
    if (!loaded)
        return loaded.error();
    const openvdb::FloatGrid& grid = **loaded;
    const openvdb::math::Transform& transform = grid.transform();
    const openvdb::Vec3d voxel = transform.voxelSize();
    // Only axis-aligned, uniform, unrotated grids map onto origin + (i, j, k) * voxelSize.
    const openvdb::Vec3d ex = transform.indexToWorld(openvdb::Vec3d(1, 0, 0)) -
                              transform.indexToWorld(openvdb::Vec3d(0, 0, 0));
    const bool axisAligned =
        std::abs(ex.y()) <= 1e-12 * voxel.x() && std::abs(ex.z()) <= 1e-12 * voxel.x();
    if (!transform.isLinear() || !transform.hasUniformScale() || !axisAligned)
        return fail(ErrorCode::Unsupported,
                    quoted(path) + ": grid '" + grid.getName() +
                        "' has a rotated, non-uniform or frustum transform; resample it to an "
                        "axis-aligned uniform grid first");

    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    if (box.empty() || grid.activeVoxelCount() == 0)
        return fail(ErrorCode::EmptyMesh,
                    quoted(path) + ": grid '" + grid.getName() + "' has no active voxels");
    const openvdb::Coord dim = box.dim();
    if (dim.x() < 2 || dim.y() < 2 || dim.z() < 2)
        return fail(ErrorCode::Unsupported,
                    quoted(path) + ": grid '" + grid.getName() + "' is only " +
                        std::to_string(dim.x()) + " x " + std::to_string(dim.y()) + " x " +
                        std::to_string(dim.z()) +
                        " voxels; a collider needs at least 2 grid points along every axis");
    const std::uint64_t points =
        std::uint64_t(dim.x()) * std::uint64_t(dim.y()) * std::uint64_t(dim.z());
    if (points > kMaxGridPoints)
        return fail(ErrorCode::SizeOverflow,
                    quoted(path) + ": active bounding box of " + std::to_string(points) +
                        " voxels exceeds the limit of " + std::to_string(kMaxGridPoints));

    format::ColliderAsset asset;
    format::ColliderMeta& meta = asset.meta;
    meta.dims = glm::uvec3(std::uint32_t(dim.x()), std::uint32_t(dim.y()), std::uint32_t(dim.z()));
    const openvdb::Vec3d origin = transform.indexToWorld(box.min());
    meta.origin = glm::dvec3(origin.x(), origin.y(), origin.z());
    meta.voxelSize = voxel.x();
    meta.storage = format::Storage::F32;
    meta.sourceFile = stringMeta(grid, kMetaSourceFile);
    meta.sourceHash = stringMeta(grid, kMetaSourceHash);
    meta.toolVersion = stringMeta(grid, kMetaToolVersion);
    meta.bake.backend = stringMeta(grid, kMetaBackend);
    meta.bake.signUsed = signMethodFromName(stringMeta(grid, kMetaSignMethod));
    if (meta.sourceFile.empty()) {
        // Not one of ours: the .vdb itself is the source.
        meta.sourceFile = path.filename().string();
        auto hash = format::hashFileHex(path);
        if (!hash)
            return hash.error();
        meta.sourceHash = *hash;
        meta.bake.backend = "vdb";
        meta.bake.signUsed = format::SignMethod::Level;
    }

    asset.distances.resize(points);
    const openvdb::Coord lo = box.min();
    // Slabs of at least ~64 K points: small grids stay on this thread.
    const std::uint32_t slab = std::uint32_t(
        std::max<std::uint64_t>(1, (std::uint64_t(1) << 16) / (std::uint64_t(dim.x()) * dim.y())));
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, meta.dims.z, slab),
                      [&](const auto& range) {
                          auto accessor = grid.getConstAccessor();
                          for (std::uint32_t k = range.begin(); k != range.end(); ++k)
                              for (std::uint32_t j = 0; j < meta.dims.y; ++j)
                                  for (std::uint32_t i = 0; i < meta.dims.x; ++i)
                                      asset.distances[asset.index(i, j, k)] =
                                          accessor.getValue(lo.offsetBy(int(i), int(j), int(k)));
                      });
    for (float d : asset.distances)
        if (!std::isfinite(d))
            return fail(ErrorCode::NonFinite,
                        quoted(path) + ": grid '" + grid.getName() + "' holds non-finite values");
    return asset;
}

} // namespace sluice::bake
