// Private: the metadata block of a collider asset, as a cereal PortableBinary archive.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::format::detail {

/// Serializes every field of `meta` as version kAssetMajor.kAssetMinor lays them out
/// (little-endian; order in AssetMeta.cpp). Strings longer than kAssetMaxStringBytes are a
/// broken contract: the writer checks them first.
std::vector<std::byte> encodeMeta(const ColliderMeta& meta);

/// Decodes a metadata block from untrusted bytes written as minor version `minor` (fields of
/// later minors are left at their defaults): bounded strings, range-checked enums and booleans,
/// and every byte consumed. Does not judge values (dims, voxel size, mass properties): the
/// reader does. BadMetadata on any failure, with `name` and the field in the message.
Result<ColliderMeta> decodeMeta(std::span<const std::byte> bytes, std::uint16_t minor,
                                const std::string& name);

/// Whether stored mass properties are usable: every value finite (else NonFinite), volume > 0
/// and the inertia tensor symmetric to 1e-9 of its largest element (else InvalidArgument); the
/// detail names the field ("meshMass.volume is -1.000000, not > 0"). The writer refuses what
/// fails; the reader rejects it as BadMetadata.
Result<void> checkMassProperties(const MassProperties& mass);

} // namespace sluice::format::detail
