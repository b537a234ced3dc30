// Validation of untrusted NanoVDB float grids: the only code that reads such a buffer unchecked.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include <glm/vec3.hpp>

#include "sluice/format/support/Result.h"

namespace sluice::format {

/// [bytes] largest NanoVDB grid a reader accepts (1 GiB, the dense limit's fp32 payload).
inline constexpr std::uint64_t kMaxNanoVdbBytes = std::uint64_t(1) << 30;

/// What a valid grid holds, as counted while walking it (not as its header claims).
struct NanoVdbTreeStats {
    std::uint64_t bytes = 0;        ///< [bytes] the whole grid buffer (GridData::mGridSize)
    std::uint32_t leafNodes = 0;    ///< 8^3 voxel nodes
    std::uint32_t lowerNodes = 0;   ///< 16^3 children (128^3 voxels) nodes
    std::uint32_t upperNodes = 0;   ///< 32^3 children (4096^3 voxels) nodes
    std::uint32_t rootTiles = 0;    ///< entries of the root table (children and value tiles)
    std::uint64_t activeVoxels = 0; ///< active leaf voxels (the narrow band)
    std::uint64_t valueTiles = 0;   ///< inactive or active constant tiles at root, upper, lower
    float background = 0.0f;        ///< [world units] the value of anything not stored
    glm::ivec3 bboxMin{0};          ///< [index] root bounding box of active values
    glm::ivec3 bboxMax{0};          ///< [index] inclusive
    glm::dvec3 voxelSize{0.0};      ///< [world units] per axis, from the grid's map
    glm::dvec3 translation{0.0};    ///< [world units] world position of index (0, 0, 0)
    std::array<char, 64> name{};    ///< grid name, NUL-terminated, cut to 63 characters
};

/// Checks that `bytes` is exactly one NanoVDB grid of this build's ABI (NanoVDB 32.x, as read by
/// NanoVDB.h and PNanoVDB.h) that can be walked safely, before anything walks it:
///  - GridData: size at least GridData + TreeData (Truncated), magic (BadMagic), major version
///    (UnsupportedVersion), grid index 0 of 1, mGridSize equal to the buffer size (SizeMismatch),
///    Float values of class LevelSet, no blind data (Unsupported), a map that is a uniform scale
///    plus a finite translation (BadMetadata, NonFinite).
///  - TreeData: each node array (leaf, lower, upper) and the root with its table lies inside the
///    buffer after the headers, 32-byte aligned, without overlapping another (OffsetOutOfRange,
///    SizeOverflow for counts whose byte size overflows or exceeds the buffer).
///  - Every child offset (root tiles, upper and lower tables) lands exactly on a node of the next
///    level down, and each node is reached once and every node is reached (OffsetOutOfRange):
///    levels only go down, so there are no cycles, and a walk costs at most the node count.
///  - Every value a lookup can return (background, tile values, leaf values) is finite
///    (NonFinite).
/// `bytes` need not be aligned (fields are copied out); messages start with `nameForMessages`.
Result<NanoVdbTreeStats> checkNanoVdbGrid(std::span<const std::byte> bytes,
                                          std::string_view nameForMessages);

} // namespace sluice::format
