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

/// How the payload is split (1.3): the samples' bytes, then one volume map per support.
struct PayloadSplit {
    std::uint64_t samplesBytes = 0;
    std::vector<double> volumeMapSupports; ///< [asset units], at most kMaxVolumeMaps
};

/// The metadata block as decoded: the collider's metadata and the payload's split.
struct DecodedMeta {
    ColliderMeta meta;
    PayloadSplit split;
    bool hasSplit = false; ///< 1.3 on; before, the samples are the whole payload
};

/// Serializes every field of `meta` and the payload's `split` as version
/// kAssetMajor.kAssetMinor lays them out (little-endian; order in AssetMeta.cpp). Strings longer
/// than kAssetMaxStringBytes are a broken contract: the writer checks them first.
std::vector<std::byte> encodeMeta(const ColliderMeta& meta, const PayloadSplit& split);

/// Decodes a metadata block from untrusted bytes written as minor version `minor` (fields of
/// later minors are left at their defaults): bounded strings, range-checked enums and booleans,
/// at most kMaxVolumeMaps supports, and every byte consumed. Does not judge values (dims, voxel
/// size, mass properties, supports): the reader does. BadMetadata on any failure, with `name`
/// and the field in the message.
Result<DecodedMeta> decodeMeta(std::span<const std::byte> bytes, std::uint16_t minor,
                               const std::string& name);

/// Whether stored mass properties are usable: every value finite (else NonFinite), volume > 0
/// and the inertia tensor symmetric to 1e-9 of its largest element (else InvalidArgument); the
/// detail names the field ("meshMass.volume is -1.000000, not > 0"). The writer refuses what
/// fails; the reader rejects it as BadMetadata.
Result<void> checkMassProperties(const MassProperties& mass);

} // namespace sluice::format::detail
