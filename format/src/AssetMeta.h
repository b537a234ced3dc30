// Private: the metadata block of a collider asset, as a cereal PortableBinary archive.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "sluice/format/ColliderAsset.h"
#include "sluice/format/Result.h"

namespace sluice::format::detail {

/// Serializes every field of `meta` (little-endian; order in AssetMeta.cpp). Strings longer
/// than kAssetMaxStringBytes are a broken contract: the writer checks them first.
std::vector<std::byte> encodeMeta(const ColliderMeta& meta);

/// Decodes a metadata block from untrusted bytes: bounded strings, range-checked enums and
/// booleans, and every byte consumed. Does not judge values (dims, voxel size): the reader does.
/// BadMetadata on any failure, with `name` and the field in the message.
Result<ColliderMeta> decodeMeta(std::span<const std::byte> bytes, const std::string& name);

} // namespace sluice::format::detail
