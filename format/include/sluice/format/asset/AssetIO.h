// Reading and writing collider asset files (format drawn in AssetHeader.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "sluice/format/asset/AssetHeader.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::format {

/// Most grid points an asset may have: 2^28 (e.g. 645^3), 1 GiB of fp32 samples. Readers reject
/// larger dims with SizeOverflow before allocating; writers refuse to write them.
inline constexpr std::uint64_t kMaxAssetPoints = std::uint64_t(1) << 28;

/// Most points a volume map may have: 2^24, the largest map the solver builds
/// (shared/Pbf.h, kVolumeMapMaxPoints).
inline constexpr std::uint64_t kMaxVolumeMapPoints = std::uint64_t(1) << 24;

/// [bytes] largest file readAsset will load: header, largest metadata block, padding,
/// kMaxAssetPoints fp32 samples and kMaxVolumeMaps maps of kMaxVolumeMapPoints, each padded.
inline constexpr std::uint64_t kMaxAssetFileBytes =
    kAssetHeaderSize + kAssetMaxMetaBytes + kAssetPayloadAlignment + kMaxAssetPoints * 4 +
    kMaxVolumeMaps * (kMaxVolumeMapPoints * 4 + kAssetPayloadAlignment);

/// Bytes per stored sample: 4 for F32, 2 for F16.
std::uint32_t bytesPerSample(Storage storage);

/// An encoded asset file and what encoding measured.
struct EncodedAsset {
    std::vector<std::byte> bytes; ///< the complete file
    /// [world units] max |stored - exact| over all samples: 0 for F32; for F16 the rounding
    /// error (and the clamp to +-65504 if a distance was beyond it). Also written into the
    /// file's metadata as meta.quantizationError.
    double quantizationError = 0.0;
};

/// Encodes `asset` as a version kAssetMajor.kAssetMinor file, storing samples as
/// asset.meta.storage says. asset.meta.quantizationError is ignored: the figure is measured
/// here, returned, and stored in the file. Refuses assets a reader would reject, with an error:
/// InvalidArgument for dims below 2, a voxel size that is not > 0, an unknown enum, a sample
/// count that differs from dims, a string over kAssetMaxStringBytes, or a meshMass with a
/// volume that is not > 0 or an asymmetric inertia tensor; SizeOverflow past kMaxAssetPoints;
/// NonFinite for a NaN or infinite sample, origin, voxel size, far grid corner or meshMass value.
Result<EncodedAsset> encodeAsset(const ColliderAsset& asset);

/// encodeAsset, then writeFileAtomic: `path` is replaced whole or left untouched. The file's
/// metadata carries the measured quantization error; call encodeAsset + writeFileAtomic to also
/// get it in hand.
Result<void> writeAsset(const std::filesystem::path& path, const ColliderAsset& asset);

/// Decodes an asset from untrusted bytes. Checks, in this order, each with its own code:
/// length >= header (Truncated); magic (BadMagic); major == kAssetMajor and minor <=
/// kAssetMinor (UnsupportedVersion); header size (BadHeader); declared file size vs. the real
/// one (Truncated if the bytes are fewer, SizeMismatch if more); section offsets and sizes:
/// overflow (SizeOverflow), metadata over kAssetMaxMetaBytes (SizeOverflow), sections outside the
/// file, overlapping, or not packed as drawn in AssetHeader.h (OffsetOutOfRange); checksum
/// (ChecksumMismatch); metadata decode, enums, strings, dims >= 2, sign convention +-1,
/// quantization error finite >= 0, and from minor 1 on the meshMass presence byte (0 or 1) and
/// its values: finite, volume > 0, inertia symmetric to 1e-9 relative (BadMetadata; a 1.0 file
/// has no meshMass and loads without one); voxel size finite (NonFinite) and > 0
/// (BadMetadata); origin and far grid corner finite (NonFinite);
/// point count overflow or over kMaxAssetPoints (SizeOverflow); payload size vs. points *
/// bytesPerSample (SizeMismatch); every sample finite (NonFinite). Allocates only after all of
/// that, and never more than the input's size. Messages start with `nameForMessages`.
Result<ColliderAsset> decodeAsset(std::span<const std::byte> bytes,
                                  std::string_view nameForMessages);

/// Reads and decodes an asset file (at most kMaxAssetFileBytes; larger is SizeOverflow before
/// reading). Io if it cannot be read; otherwise as decodeAsset, with the path in messages.
Result<ColliderAsset> readAsset(const std::filesystem::path& path);

} // namespace sluice::format
