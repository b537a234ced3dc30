// Packs and unpacks the fixed collider asset header (layout in AssetHeader.h).
#include "sluice/format/asset/AssetHeader.h"

#include <cstring>

#include "asset/Bytes.h"

namespace sluice::format {

using detail::loadLE;
using detail::storeLE;
namespace off = header_offset;

std::array<std::byte, kAssetHeaderSize> packAssetHeader(const AssetHeader& header) {
    std::array<std::byte, kAssetHeaderSize> bytes{};
    std::memcpy(bytes.data() + off::kMagic, header.magic.data(), header.magic.size());
    storeLE(bytes.data() + off::kMajor, header.major);
    storeLE(bytes.data() + off::kMinor, header.minor);
    storeLE(bytes.data() + off::kHeaderSize, header.headerSize);
    storeLE(bytes.data() + off::kFileSize, header.fileSize);
    storeLE(bytes.data() + off::kMetaOffset, header.metaOffset);
    storeLE(bytes.data() + off::kMetaSize, header.metaSize);
    storeLE(bytes.data() + off::kPayloadOffset, header.payloadOffset);
    storeLE(bytes.data() + off::kPayloadSize, header.payloadSize);
    storeLE(bytes.data() + off::kChecksum, header.checksum);
    return bytes;
}

AssetHeader unpackAssetHeader(std::span<const std::byte, kAssetHeaderSize> bytes) {
    AssetHeader header;
    std::memcpy(header.magic.data(), bytes.data() + off::kMagic, header.magic.size());
    header.major = loadLE<std::uint16_t>(bytes.data() + off::kMajor);
    header.minor = loadLE<std::uint16_t>(bytes.data() + off::kMinor);
    header.headerSize = loadLE<std::uint32_t>(bytes.data() + off::kHeaderSize);
    header.fileSize = loadLE<std::uint64_t>(bytes.data() + off::kFileSize);
    header.metaOffset = loadLE<std::uint64_t>(bytes.data() + off::kMetaOffset);
    header.metaSize = loadLE<std::uint64_t>(bytes.data() + off::kMetaSize);
    header.payloadOffset = loadLE<std::uint64_t>(bytes.data() + off::kPayloadOffset);
    header.payloadSize = loadLE<std::uint64_t>(bytes.data() + off::kPayloadSize);
    header.checksum = loadLE<std::uint64_t>(bytes.data() + off::kChecksum);
    return header;
}

} // namespace sluice::format
