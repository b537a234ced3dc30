// A pre-flight walk over a .vdb file's header and grid descriptors, before OpenVDB parses it.
//
// OpenVDB reads trees without checking its reads, and when the stream throws instead it leaks
// the root child it was reading (RootNode::readTopology, OpenVDB 10). A file whose grids all
// end inside it cannot run out mid-tree, so a cut-off file is caught here, cleanly, first.
//
// Layout of a seekable file (io::File, format version >= 221; all integers little-endian):
//
//   int64 magic 0x56444220 | uint32 file version | uint32 library major | uint32 library minor
//   char hasGridOffsets | [char compressed, versions 220-221 only] | char uuid[36]
//   file metadata: uint32 count, then per item: string name, string type, uint32 size, bytes
//   int32 grid count, then per grid:
//     string uniqueName | string type | string instanceParent | int64 gridPos, blockPos, endPos
//     ... the grid's bytes, [gridPos, endPos) ...      (the next descriptor starts at endPos)
//   string = uint32 length + that many bytes
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "sluice/format/support/Result.h"

namespace sluice::bake::detail {

/// Walks the header, file metadata and grid descriptors of `path` (already checked to start
/// with the VDB magic) and checks that every grid ends inside the file. Truncated when
/// something ends past the end of the file, MeshImport when the offsets contradict each other.
/// Files without grid offsets (written by io::Stream) or of unknown versions are left to
/// OpenVDB: this returns success for them.
inline Result<void> checkVdbExtents(const std::filesystem::path& path) {
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    if (ec)
        return fail(ErrorCode::Io, "cannot read the size of '" + path.string() + "'");
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return fail(ErrorCode::Io, "cannot open '" + path.string() + "' for reading");

    const std::string name = "'" + path.string() + "'";
    std::uint64_t at = 0;
    auto truncated = [&](const std::string& what) {
        return fail(ErrorCode::Truncated, name + " is truncated: " + what + " runs past its end (" +
                                              std::to_string(size) +
                                              " bytes); export or save it again");
    };
    auto read = [&](void* out, std::uint64_t n) {
        if (n > size - at)
            return false;
        in.read(static_cast<char*>(out), std::streamsize(n));
        at += n;
        return bool(in);
    };
    auto skip = [&](std::uint64_t n) {
        if (n > size - at)
            return false;
        at += n;
        in.seekg(std::streamoff(at));
        return bool(in);
    };
    auto skipString = [&] {
        std::uint32_t length = 0;
        return read(&length, sizeof length) && skip(length);
    };

    std::uint64_t magic = 0;
    std::uint32_t version = 0, libraryMajor = 0, libraryMinor = 0;
    char hasGridOffsets = 0;
    if (!read(&magic, sizeof magic) || !read(&version, sizeof version) ||
        !read(&libraryMajor, sizeof libraryMajor) || !read(&libraryMinor, sizeof libraryMinor) ||
        !read(&hasGridOffsets, 1))
        return truncated("the header");
    if (version < 221 || version > 224 || hasGridOffsets == 0)
        return {};
    if (version < 222 && !skip(1))
        return truncated("the header");
    if (!skip(36))
        return truncated("the header");

    std::uint32_t metaCount = 0;
    if (!read(&metaCount, sizeof metaCount))
        return truncated("the file metadata");
    for (std::uint32_t m = 0; m < metaCount; ++m) {
        std::uint32_t bytes = 0;
        if (!skipString() || !skipString() || !read(&bytes, sizeof bytes) || !skip(bytes))
            return truncated("the file metadata");
    }

    std::int32_t gridCount = 0;
    if (!read(&gridCount, sizeof gridCount))
        return truncated("the grid count");
    if (gridCount < 0)
        return fail(ErrorCode::MeshImport, name + " is corrupt: negative grid count");
    for (std::int32_t g = 0; g < gridCount; ++g) {
        const std::string what =
            "grid " + std::to_string(g + 1) + " of " + std::to_string(gridCount);
        std::int64_t gridPos = 0, blockPos = 0, endPos = 0;
        if (!skipString() || !skipString() || !skipString() || !read(&gridPos, sizeof gridPos) ||
            !read(&blockPos, sizeof blockPos) || !read(&endPos, sizeof endPos))
            return truncated("the descriptor of " + what);
        if (gridPos != std::int64_t(at) || blockPos < gridPos || endPos < blockPos)
            return fail(ErrorCode::MeshImport,
                        name + " is corrupt: inconsistent offsets in the descriptor of " + what);
        if (std::uint64_t(endPos) > size)
            return truncated(what);
        if (!skip(std::uint64_t(endPos) - at))
            return truncated(what);
    }
    return {};
}

} // namespace sluice::bake::detail
