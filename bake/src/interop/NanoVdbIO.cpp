// NanoVDB interchange: .nvdb files written from sparse assets, read back as hostile input.
#include "sluice/bake/interop/NanoVdbIO.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <string>

#include "interop/NanoVdbHeaders.h"
#include "interop/VdbMesh.h"

#include "sluice/format/support/AtomicFile.h"

namespace fs = std::filesystem;

namespace sluice::bake {

namespace {

using detail::quoted;

nanovdb::GridHandle<nanovdb::HostBuffer> handleOf(const format::GridBytes& grid) {
    auto buffer = nanovdb::HostBuffer::create(grid.size());
    std::memcpy(buffer.data(), grid.data(), grid.size());
    return nanovdb::GridHandle<nanovdb::HostBuffer>(std::move(buffer));
}

/// [bytes] longest grid name accepted in a .nvdb file's metadata.
constexpr std::uint32_t kMaxNameBytes = 1u << 16;

} // namespace

Result<std::vector<std::byte>> encodeNvdb(const format::GridBytes& grid) {
    try {
        const auto handle = handleOf(grid);
        nanovdb::io::Segment segment(nanovdb::io::Codec::NONE);
        segment.add(handle);
        segment.meta[0].fileSize = grid.size(); // uncompressed: the grid as it is in memory
        std::ostringstream os(std::ios::binary);
        segment.write(os);
        os.write(reinterpret_cast<const char*>(grid.data()), std::streamsize(grid.size()));
        const std::string s = std::move(os).str();
        const auto* p = reinterpret_cast<const std::byte*>(s.data());
        return std::vector<std::byte>(p, p + s.size());
    } catch (const std::exception& e) {
        return fail(ErrorCode::Unsupported,
                    std::string("NanoVDB cannot write the grid: ") + e.what());
    }
}

Result<void> exportNvdb(const format::ColliderAsset& asset, const fs::path& path) {
    if (!asset.sparse())
        return fail(ErrorCode::InvalidArgument,
                    "cannot export to " + quoted(path) +
                        ": a dense asset has no NanoVDB grid; bake it with --sparse, or export "
                        "it as .vdb");
    auto bytes = encodeNvdb(asset.grid);
    if (!bytes)
        return bytes.error();
    return format::writeFileAtomic(path, *bytes);
}

Result<format::GridBytes> readNvdbGrid(const fs::path& path) {
    auto file = format::readFileBytes(path, kMaxNvdbFileBytes);
    if (!file)
        return file.error();
    const std::vector<std::byte>& bytes = *file;
    const std::string name = path.string();
    auto bad = [&](ErrorCode code, const std::string& what) {
        return fail(code, name + ": " + what);
    };
    using Header = nanovdb::io::Header;
    using Meta = nanovdb::io::MetaData;
    static_assert(sizeof(Header) == 16 && sizeof(Meta) == 176, "NanoVDB 32.x file layout");
    if (bytes.size() < sizeof(Header))
        return bad(ErrorCode::Truncated, "shorter than a NanoVDB file header");
    Header header;
    std::memcpy(&header, bytes.data(), sizeof(Header));
    if (header.magic != NANOVDB_MAGIC_NUMBER)
        return bad(ErrorCode::BadMagic, "not a NanoVDB file (wrong magic number)");
    if (header.version.getMajor() != NANOVDB_MAJOR_VERSION_NUMBER)
        return bad(ErrorCode::UnsupportedVersion,
                   "NanoVDB file version " + std::to_string(header.version.getMajor()) +
                       ", this build reads " + std::to_string(NANOVDB_MAJOR_VERSION_NUMBER));
    if (header.codec != nanovdb::io::Codec::NONE)
        return bad(ErrorCode::Unsupported, "compressed grids are not supported; write it with "
                                           "nanovdb_convert without compression");
    if (header.gridCount == 0)
        return bad(ErrorCode::EmptyMesh, "the file holds no grid");
    // The metadata of every grid of the first segment, then the grids, in order.
    std::uint64_t at = sizeof(Header);
    Meta first{};
    for (std::uint32_t g = 0; g < header.gridCount; ++g) {
        if (bytes.size() - at < sizeof(Meta))
            return bad(ErrorCode::Truncated, "the grid metadata ends early");
        Meta meta;
        std::memcpy(&meta, bytes.data() + at, sizeof(Meta));
        if (meta.nameSize > kMaxNameBytes || bytes.size() - at - sizeof(Meta) < meta.nameSize)
            return bad(ErrorCode::Truncated, "a grid name runs past the end of the file");
        at += sizeof(Meta) + meta.nameSize;
        if (g == 0)
            first = meta;
    }
    if (first.codec != nanovdb::io::Codec::NONE || first.fileSize != first.gridSize)
        return bad(ErrorCode::Unsupported, "the first grid is compressed");
    if (first.gridSize > format::kMaxNanoVdbBytes)
        return bad(ErrorCode::SizeOverflow, "the first grid's size exceeds the limit");
    if (bytes.size() - at < first.gridSize)
        return bad(ErrorCode::Truncated, "the first grid ends early");
    const auto begin = bytes.begin() + std::ptrdiff_t(at);
    format::GridBytes grid(begin, begin + std::ptrdiff_t(first.gridSize));
    auto stats = format::checkNanoVdbGrid(grid, name);
    if (!stats)
        return stats.error();
    return grid;
}

Result<ImportedMesh> importNvdbLevelSet(const fs::path& path, double scale) {
    auto grid = readNvdbGrid(path);
    if (!grid)
        return grid.error();
    initOpenVdb();
    openvdb::FloatGrid::Ptr vdb;
    try {
        const auto* nano = reinterpret_cast<const nanovdb::NanoGrid<float>*>(grid->data());
        vdb = nanovdb::nanoToOpenVDB(*nano);
    } catch (const std::exception& e) {
        return fail(ErrorCode::MeshImport, "cannot convert " + quoted(path) + ": " + e.what());
    }
    return detail::meshLevelSet(*vdb, path, scale);
}

openvdb::FloatGrid::Ptr detail::sparseToOpenVdb(const format::ColliderAsset& asset) {
    const auto* nano = reinterpret_cast<const nanovdb::NanoGrid<float>*>(asset.grid.data());
    openvdb::FloatGrid::Ptr grid = nanovdb::nanoToOpenVDB(*nano);
    grid->setName("sdf");
    return grid;
}

} // namespace sluice::bake
