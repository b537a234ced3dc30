// Decodes collider asset files, treating every byte as untrusted (checks in AssetIO.h order).
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

#include "asset/AssetMeta.h"
#include "asset/Bytes.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/GridSamples.h"
#include "sluice/format/asset/Half.h"
#include "sluice/format/asset/NanoVdbCheck.h"
#include "sluice/format/support/AtomicFile.h"
#include "sluice/format/support/Hash.h"

namespace sluice::format {

namespace {

using detail::checkedAdd;
using detail::checkedMul;
using detail::loadLE;

constexpr const char* kRebake = "; re-bake with sluice-bake";

std::string str(std::uint64_t v) {
    return std::to_string(v);
}

// Section layout checks, after the header fields themselves are known to be sane.
Result<void> checkSections(const AssetHeader& h, const std::string& name) {
    auto bad = [&](ErrorCode code, const std::string& what) {
        return fail(code, name + ": " + what + kRebake);
    };
    const auto metaEnd = checkedAdd(h.metaOffset, h.metaSize);
    const auto payloadEnd = checkedAdd(h.payloadOffset, h.payloadSize);
    if (!metaEnd || !payloadEnd)
        return bad(ErrorCode::SizeOverflow, "a section offset + size overflows 64 bits");
    if (h.metaSize > kAssetMaxMetaBytes)
        return bad(ErrorCode::SizeOverflow, "metadata block of " + str(h.metaSize) +
                                                " bytes exceeds the limit of " +
                                                str(kAssetMaxMetaBytes));
    if (h.metaOffset < h.headerSize || *metaEnd > h.fileSize)
        return bad(ErrorCode::OffsetOutOfRange,
                   "metadata [" + str(h.metaOffset) + ", " + str(*metaEnd) +
                       ") lies outside the file body [" + str(h.headerSize) + ", " +
                       str(h.fileSize) + ")");
    if (h.payloadOffset < *metaEnd || *payloadEnd > h.fileSize)
        return bad(ErrorCode::OffsetOutOfRange,
                   "payload [" + str(h.payloadOffset) + ", " + str(*payloadEnd) +
                       ") overlaps the metadata or lies outside the file (" + str(h.fileSize) +
                       " bytes)");
    // Sections are packed as drawn in AssetHeader.h: no bytes belong to nothing.
    const auto alignedMetaEnd = detail::alignUp(*metaEnd, kAssetPayloadAlignment);
    if (h.metaOffset != h.headerSize || !alignedMetaEnd || h.payloadOffset != *alignedMetaEnd ||
        *payloadEnd != h.fileSize)
        return bad(ErrorCode::OffsetOutOfRange,
                   "sections are not laid out as version 1 requires (metadata at " +
                       str(h.metaOffset) + ", payload at " + str(h.payloadOffset) + ")");
    return {};
}

// A sparse asset's metadata: fp32, a band, and a payload the size limit allows. dims only bound
// the baked region, so their product is not limited; the grid's own checks come later.
Result<std::uint64_t> checkSparseMeta(const ColliderMeta& m, std::uint64_t samplesBytes,
                                      const std::string& name) {
    auto bad = [&](ErrorCode code, const std::string& what) {
        return fail(code, name + ": " + what + kRebake);
    };
    if (m.storage != Storage::F32)
        return bad(ErrorCode::BadMetadata,
                   "a sparse asset stores f32 values, not " + std::string(storageName(m.storage)));
    if (!std::isfinite(m.bandWidth) || !(m.bandWidth > 0.0))
        return bad(ErrorCode::BadMetadata, "band width is not a finite value > 0");
    if (samplesBytes > kMaxNanoVdbBytes)
        return bad(ErrorCode::SizeOverflow, "NanoVDB payload of " + str(samplesBytes) +
                                                " bytes exceeds the limit of " +
                                                str(kMaxNanoVdbBytes));
    return std::uint64_t(0);
}

// The NanoVDB payload, walked by checkNanoVdbGrid, then its map against the metadata's grid.
Result<GridBytes> decodeSparse(std::span<const std::byte> payload, const ColliderMeta& m,
                               const std::string& name) {
    // Copied first, into 32-byte-aligned memory: the check and every later walk see the same
    // bytes, and NanoVDB.h may then read them in place.
    GridBytes grid(payload.begin(), payload.end());
    auto stats = checkNanoVdbGrid(grid, name);
    if (!stats)
        return fail(stats.error().code, stats.error().detail + kRebake);
    const double h = m.voxelSize;
    for (int a = 0; a < 3; ++a)
        if (std::abs(stats->voxelSize[a] - h) > 1e-9 * h ||
            std::abs(stats->translation[a] - m.origin[a]) > 1e-6 * h)
            return fail(ErrorCode::BadMetadata,
                        name +
                            ": the NanoVDB grid's transform differs from the asset's origin "
                            "and voxel size" +
                            kRebake);
    return grid;
}

// Value checks on decoded metadata, then the point count against the samples' bytes.
Result<std::uint64_t> checkMeta(const ColliderMeta& m, std::uint64_t samplesBytes,
                                const std::string& name) {
    auto bad = [&](ErrorCode code, const std::string& what) {
        return fail(code, name + ": " + what + kRebake);
    };
    if (m.dims.x < 2 || m.dims.y < 2 || m.dims.z < 2)
        return bad(ErrorCode::BadMetadata, "grid dims " + str(m.dims.x) + "x" + str(m.dims.y) +
                                               "x" + str(m.dims.z) + " (each must be >= 2)");
    if (m.signConvention != -1 && m.signConvention != 1)
        return bad(ErrorCode::BadMetadata,
                   "sign convention " + std::to_string(int(m.signConvention)) + " (-1 or +1)");
    if (!std::isfinite(m.quantizationError) || m.quantizationError < 0.0)
        return bad(ErrorCode::BadMetadata, "quantization error is not a finite value >= 0");
    if (m.meshMass)
        if (Result<void> mass = detail::checkMassProperties(*m.meshMass); !mass)
            return bad(ErrorCode::BadMetadata, mass.error().detail);
    if (!std::isfinite(m.voxelSize))
        return bad(ErrorCode::NonFinite, "voxel size is not finite");
    if (!(m.voxelSize > 0.0))
        return bad(ErrorCode::BadMetadata,
                   "voxel size " + std::to_string(m.voxelSize) + " is not > 0");
    if (!std::isfinite(m.origin.x) || !std::isfinite(m.origin.y) || !std::isfinite(m.origin.z))
        return bad(ErrorCode::NonFinite, "grid origin is not finite");
    // The far corner must be finite too, or samplers would divide infinities.
    const glm::dvec3 far = m.origin + glm::dvec3(m.dims - glm::uvec3(1)) * m.voxelSize;
    if (!std::isfinite(far.x) || !std::isfinite(far.y) || !std::isfinite(far.z))
        return bad(ErrorCode::NonFinite,
                   "grid extent overflows (voxel size " + std::to_string(m.voxelSize) + ")");

    if (m.layout == Layout::Sparse)
        return checkSparseMeta(m, samplesBytes, name);
    if (m.bandWidth != 0.0)
        return bad(ErrorCode::BadMetadata, "a dense asset with a band width");

    // dims are u32, so x*y cannot overflow 64 bits; the product with z can.
    const auto points = checkedMul(std::uint64_t(m.dims.x) * m.dims.y, m.dims.z);
    if (!points || *points > kMaxAssetPoints)
        return bad(ErrorCode::SizeOverflow, "grid " + str(m.dims.x) + "x" + str(m.dims.y) + "x" +
                                                str(m.dims.z) + " exceeds the limit of " +
                                                str(kMaxAssetPoints) + " points");
    const std::uint64_t expected = *points * bytesPerSample(m.storage); // <= 2^30, no overflow
    if (samplesBytes != expected)
        return bad(ErrorCode::SizeMismatch, "samples take " + str(samplesBytes) + " bytes but " +
                                                str(*points) + " points need " + str(expected));
    return *points;
}

// Converts the payload to floats; the first NaN or infinity is reported with its grid point.
Result<std::vector<float>> decodeSamples(std::span<const std::byte> payload, const ColliderMeta& m,
                                         std::uint64_t points, const std::string& name) {
    std::vector<float> out(static_cast<std::size_t>(points));
    const bool half = m.storage == Storage::F16;
    for (std::size_t n = 0; n < out.size(); ++n) {
        const float v = half ? halfToFloat(loadLE<std::uint16_t>(payload.data() + 2 * n))
                             : std::bit_cast<float>(loadLE<std::uint32_t>(payload.data() + 4 * n));
        if (!std::isfinite(v)) {
            const std::uint64_t i = n % m.dims.x;
            const std::uint64_t j = (n / m.dims.x) % m.dims.y;
            const std::uint64_t k = n / (std::uint64_t(m.dims.x) * m.dims.y);
            return fail(ErrorCode::NonFinite, name + ": sample (" + str(i) + ", " + str(j) + ", " +
                                                  str(k) + ") is " +
                                                  (std::isnan(v) ? "NaN" : "infinite") + kRebake);
        }
        out[n] = v;
    }
    return out;
}

// The payload's split as the metadata gives it (1.3 on), else all of it samples; the samples
// must fit in it.
Result<detail::PayloadSplit> payloadSplit(const detail::DecodedMeta& decoded, const AssetHeader& h,
                                          const std::string& name) {
    if (!decoded.hasSplit)
        return detail::PayloadSplit{h.payloadSize, {}};
    if (decoded.split.samplesBytes > h.payloadSize)
        return fail(ErrorCode::SizeMismatch,
                    name + ": the samples' " + str(decoded.split.samplesBytes) +
                        " bytes exceed the payload's " + str(h.payloadSize) + kRebake);
    return decoded.split;
}

// The volume maps after the samples: each support finite, > 0 and apart from the others, the
// payload exactly the samples and the maps (each on a 16-byte boundary), every value finite.
Result<std::vector<VolumeMap>> decodeVolumeMaps(std::span<const std::byte> payload,
                                                const detail::PayloadSplit& split,
                                                const ColliderAsset& asset,
                                                const std::string& name) {
    auto bad = [&](ErrorCode code, const std::string& what) {
        return fail(code, name + ": " + what + kRebake);
    };
    const std::vector<double>& supports = split.volumeMapSupports;
    if (supports.empty()) {
        if (payload.size() != split.samplesBytes)
            return bad(ErrorCode::SizeMismatch, "payload is " + str(payload.size()) +
                                                    " bytes but its samples take " +
                                                    str(split.samplesBytes));
        return std::vector<VolumeMap>{};
    }
    const std::uint64_t points = volumeMapPoints(asset);
    if (points > kMaxVolumeMapPoints)
        return bad(ErrorCode::SizeOverflow, "volume maps of " + str(points) +
                                                " points exceed the limit of " +
                                                str(kMaxVolumeMapPoints));
    const std::uint64_t mapBytes = points * 4;
    const std::uint64_t stride = *detail::alignUp(mapBytes, kAssetPayloadAlignment);
    const std::uint64_t first = *detail::alignUp(split.samplesBytes, kAssetPayloadAlignment);
    const std::uint64_t expected = first + (supports.size() - 1) * stride + mapBytes;
    if (payload.size() != expected)
        return bad(ErrorCode::SizeMismatch, "payload is " + str(payload.size()) +
                                                " bytes but the samples and " +
                                                str(supports.size()) + " volume maps of " +
                                                str(points) + " points need " + str(expected));
    std::vector<VolumeMap> maps(supports.size());
    for (std::size_t m = 0; m < maps.size(); ++m) {
        const double s = supports[m];
        if (!std::isfinite(s) || !(s > 0.0))
            return bad(ErrorCode::BadMetadata, "volume map " + str(m) + " has support " +
                                                   std::to_string(s) + ", not a finite value > 0");
        for (std::size_t o = 0; o < m; ++o)
            if (std::abs(maps[o].support - s) <= kVolumeMapSupportTolerance * s)
                return bad(ErrorCode::BadMetadata,
                           "volume maps " + str(o) + " and " + str(m) + " have the same support");
        maps[m].support = s;
        maps[m].values.resize(std::size_t(points));
        const std::byte* in = payload.data() + first + m * stride;
        for (std::size_t n = 0; n < maps[m].values.size(); ++n) {
            const float v = std::bit_cast<float>(loadLE<std::uint32_t>(in + 4 * n));
            if (!std::isfinite(v))
                return bad(ErrorCode::NonFinite, "volume map " + str(m) + " point " + str(n) +
                                                     " is " + (std::isnan(v) ? "NaN" : "infinite"));
            maps[m].values[n] = v;
        }
    }
    return maps;
}

} // namespace

Result<ColliderAsset> decodeAsset(std::span<const std::byte> bytes,
                                  std::string_view nameForMessages) {
    const std::string name(nameForMessages);
    const std::uint64_t actualSize = bytes.size();

    if (actualSize < kAssetHeaderSize)
        return fail(ErrorCode::Truncated, name + ": " + str(actualSize) +
                                              " bytes, shorter than the " + str(kAssetHeaderSize) +
                                              "-byte header" + kRebake);
    const AssetHeader h = unpackAssetHeader(bytes.first<kAssetHeaderSize>());

    if (std::memcmp(h.magic.data(), kAssetMagic.data(), kAssetMagic.size()) != 0)
        return fail(ErrorCode::BadMagic,
                    name + ": not a Sluice collider asset (wrong magic bytes); pass a file "
                           "written by sluice-bake");
    if (h.major != kAssetMajor || h.minor > kAssetMinor)
        return fail(ErrorCode::UnsupportedVersion,
                    name + ": format version " + str(h.major) + "." + str(h.minor) +
                        ", this build reads " + str(kAssetMajor) + ".0 to " + str(kAssetMajor) +
                        "." + str(kAssetMinor) + kRebake + " of this version");
    if (h.headerSize != kAssetHeaderSize)
        return fail(ErrorCode::BadHeader, name + ": header size " + str(h.headerSize) +
                                              ", version 1 headers are " + str(kAssetHeaderSize) +
                                              " bytes" + kRebake);
    if (h.fileSize > actualSize)
        return fail(ErrorCode::Truncated, name + ": " + str(actualSize) +
                                              " bytes but the header says " + str(h.fileSize) +
                                              " (incomplete copy?)" + kRebake);
    if (h.fileSize < actualSize)
        return fail(ErrorCode::SizeMismatch, name + ": " + str(actualSize) +
                                                 " bytes but the header says " + str(h.fileSize) +
                                                 " (trailing bytes)" + kRebake);
    if (auto sections = checkSections(h, name); !sections)
        return sections.error();

    const std::uint64_t checksum = xxh3(bytes.subspan(kAssetHeaderSize));
    if (checksum != h.checksum)
        return fail(ErrorCode::ChecksumMismatch,
                    name + ": checksum " + hex64(checksum) + " differs from the stored " +
                        hex64(h.checksum) + " (file corrupted after writing)" + kRebake);

    auto decoded = detail::decodeMeta(bytes.subspan(h.metaOffset, h.metaSize), h.minor, name);
    if (!decoded)
        return decoded.error();
    auto split = payloadSplit(*decoded, h, name);
    if (!split)
        return split.error();
    const ColliderMeta& meta = decoded->meta;
    auto points = checkMeta(meta, split->samplesBytes, name);
    if (!points)
        return points.error();
    const std::span<const std::byte> payload = bytes.subspan(h.payloadOffset, h.payloadSize);
    const std::span<const std::byte> samplesBytes = payload.first(split->samplesBytes);
    ColliderAsset asset;
    asset.meta = meta;
    if (meta.layout == Layout::Sparse) {
        auto grid = decodeSparse(samplesBytes, meta, name);
        if (!grid)
            return grid.error();
        asset.grid = std::move(*grid);
    } else {
        auto samples = decodeSamples(samplesBytes, meta, *points, name);
        if (!samples)
            return samples.error();
        asset.distances = std::move(*samples);
    }
    auto maps = decodeVolumeMaps(payload, *split, asset, name);
    if (!maps)
        return maps.error();
    asset.volumeMaps = std::move(*maps);
    return asset;
}

Result<ColliderAsset> readAsset(const std::filesystem::path& path) {
    auto bytes = readFileBytes(path, kMaxAssetFileBytes);
    if (!bytes)
        return bytes.error();
    return decodeAsset(*bytes, path.string());
}

} // namespace sluice::format
