// The fixed 64-byte header at the start of every collider asset file, and its byte layout.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace sluice::format {

/*
 Collider asset file, version 1.3 (1.1: exact mesh mass properties; 1.2: the layout, sparse
 NanoVDB payloads; 1.3: volume maps baked with the collider). All integers little-endian;
 offsets and sizes in bytes.

   offset  size  field
  +------+------+--------------------------------------------------------------------------+
  |    0 |    8 | magic  89 'S' 'L' 'C' 0D 0A 1A 0A   (PNG-style: catches text-mode copies)|
  |    8 |    2 | major version (u16) = 1      another major is rejected                   |
  |   10 |    2 | minor version (u16) = 3      older minors load; newer ones are rejected  |
  |   12 |    4 | header size (u32) = 64                                                   |
  |   16 |    8 | file size (u64)              must equal the real size                    |
  |   24 |    8 | metadata offset (u64) = 64   (right after the header)                    |
  |   32 |    8 | metadata size (u64)          <= kMaxAssetMetaBytes                       |
  |   40 |    8 | payload offset (u64)         metadata end rounded up to 16               |
  |   48 |    8 | payload size (u64)           samples, then the volume maps (1.3)         |
  |   56 |    8 | checksum (u64)               XXH3-64 of bytes [64, file size)            |
  +------+------+--------------------------------------------------------------------------+
  |   64 |    m | metadata: cereal PortableBinary archive, little-endian (AssetMeta.cpp):  |
  |      |      |  +0  u8 endianness flag = 1 (written by cereal)                          |
  |      |      |  +1  u32 dims.x, dims.y, dims.z          [grid points]                   |
  |      |      | +13  f64 origin.x, origin.y, origin.z    [world units]                   |
  |      |      | +37  f64 voxelSize                       [world units]                   |
  |      |      | +45  u8 storage, i8 signConvention                                       |
  |      |      | +47  strings (u64 length + UTF-8 bytes): sourceFile, sourceHash, then    |
  |      |      |      bake params, toolVersion, mesh diagnostics, validation figures,     |
  |      |      |      quantizationError (f64); see AssetMeta.cpp for the exact order      |
  |      |      | 1.1: u8 meshMass present (0 or 1); if 1, f64 volume, centerOfMass x y z, |
  |      |      |      inertia (3x3, row-major): 13 f64 = 104 bytes (absent in 1.0 files)  |
  |      |      | 1.2: u8 layout (0 dense, 1 sparse), f64 bandWidth [voxels] (absent in    |
  |      |      |      1.0 and 1.1 files, which are dense)                                 |
  |      |      | 1.3: u64 samples size [bytes], u32 volume map count (<= kMaxVolumeMaps), |
  |      |      |      then each map's support, f64 [asset units] (absent before 1.3: the  |
  |      |      |      samples are the whole payload and there are no maps)                |
  +------+------+--------------------------------------------------------------------------+
  |      |  0-15| zero padding so the payload starts on a 16-byte boundary                 |
  +------+------+--------------------------------------------------------------------------+
  |   p  |    n | dense payload: dims.x*dims.y*dims.z samples, f32 or f16 (storage),       |
  |      |      | x fastest: sample (i, j, k) at p + (i + dims.x*(j + dims.y*k)) * bytes   |
  |      |      | sparse payload: one NanoVDB float level-set grid (GridData, TreeData,    |
  |      |      | leaf/lower/upper node arrays, root + tiles), exactly its mGridSize bytes;|
  |      |      | index (i, j, k) is the point origin + (i, j, k) * voxelSize. Checked by  |
  |      |      | checkNanoVdbGrid (NanoVdbCheck.h) before anything walks it.              |
  |      |      | 1.3: the samples take the first `samples size` bytes; then each volume   |
  |      |      | map, starting on a 16-byte boundary (zero padding before it): one f32    |
  |      |      | per map point (volumeMapPoints: every grid point of a dense grid, 512 per|
  |      |      | leaf of a sparse one, in the tree's leaf order), the map's points only.  |
  +------+------+--------------------------------------------------------------------------+

 The checksum covers everything after the header: metadata, padding and payload. The header
 fields are each checked on their own (magic, version, sizes, offsets), so every byte of the file
 is verified before anything is decoded.
*/

/// File magic, compared with memcmp.
inline constexpr std::array<std::uint8_t, 8> kAssetMagic = {0x89, 'S',  'L',  'C',
                                                            0x0D, 0x0A, 0x1A, 0x0A};
/// Major version this build reads and writes; files with another major are rejected.
inline constexpr std::uint16_t kAssetMajor = 1;
/// Minor version this build writes; it reads this one and every older one.
inline constexpr std::uint16_t kAssetMinor = 3;
/// First minor version whose metadata has ColliderMeta::meshMass (1.1).
inline constexpr std::uint16_t kAssetMinorMeshMass = 1;
/// First minor version with the layout and band width fields, after meshMass (sparse NanoVDB
/// payloads, 1.2). Older files are dense.
inline constexpr std::uint16_t kAssetMinorSparse = 2;
/// First minor version with the samples' size and the volume maps' supports, after the band
/// width (1.3). Older files have no volume maps.
inline constexpr std::uint16_t kAssetMinorVolumeMaps = 3;
/// Most volume maps one asset holds (one per kernel radius it is baked for).
inline constexpr std::uint32_t kMaxVolumeMaps = 8;
/// [bytes] size of the fixed header; the metadata block starts right after it.
inline constexpr std::size_t kAssetHeaderSize = 64;
/// [bytes] the payload starts on a multiple of this (zero padding after the metadata).
inline constexpr std::uint64_t kAssetPayloadAlignment = 16;
/// [bytes] largest metadata block a reader accepts (it is a few hundred bytes in practice).
inline constexpr std::uint64_t kAssetMaxMetaBytes = 1u << 20;
/// [bytes] longest string in the metadata (file names, hashes, tool version).
inline constexpr std::uint64_t kAssetMaxStringBytes = 4096;

/// The header fields, in host byte order. Use packAssetHeader/unpackAssetHeader for the bytes.
struct AssetHeader {
    std::array<std::uint8_t, 8> magic = kAssetMagic;
    std::uint16_t major = kAssetMajor;
    std::uint16_t minor = kAssetMinor;
    std::uint32_t headerSize = kAssetHeaderSize; ///< [bytes]
    std::uint64_t fileSize = 0;                  ///< [bytes] whole file
    std::uint64_t metaOffset = 0;                ///< [bytes] from the start of the file
    std::uint64_t metaSize = 0;                  ///< [bytes]
    std::uint64_t payloadOffset = 0;             ///< [bytes] from the start of the file
    std::uint64_t payloadSize = 0;               ///< [bytes]
    std::uint64_t checksum = 0;                  ///< XXH3-64 of bytes [headerSize, fileSize)
};

/// Byte offsets of the header fields (the diagram above), for tools and tests.
namespace header_offset {
inline constexpr std::size_t kMagic = 0;
inline constexpr std::size_t kMajor = 8;
inline constexpr std::size_t kMinor = 10;
inline constexpr std::size_t kHeaderSize = 12;
inline constexpr std::size_t kFileSize = 16;
inline constexpr std::size_t kMetaOffset = 24;
inline constexpr std::size_t kMetaSize = 32;
inline constexpr std::size_t kPayloadOffset = 40;
inline constexpr std::size_t kPayloadSize = 48;
inline constexpr std::size_t kChecksum = 56;
} // namespace header_offset

/// Byte offsets inside the metadata block of its fixed-size leading fields (the diagram above),
/// so tools can read dims without cereal, and tests can edit them.
namespace meta_offset {
inline constexpr std::size_t kEndianFlag = 0;      ///< u8, 1 = little-endian
inline constexpr std::size_t kDims = 1;            ///< 3 x u32
inline constexpr std::size_t kOrigin = 13;         ///< 3 x f64
inline constexpr std::size_t kVoxelSize = 37;      ///< f64
inline constexpr std::size_t kStorage = 45;        ///< u8
inline constexpr std::size_t kSignConvention = 46; ///< i8
inline constexpr std::size_t kSourceFile = 47;     ///< u64 length, then the bytes
} // namespace meta_offset

/// The 64 header bytes for `header`, little-endian.
std::array<std::byte, kAssetHeaderSize> packAssetHeader(const AssetHeader& header);

/// Reads the header fields from the first 64 bytes of a file. Checks nothing: the reader
/// validates the fields one by one.
AssetHeader unpackAssetHeader(std::span<const std::byte, kAssetHeaderSize> bytes);

} // namespace sluice::format
