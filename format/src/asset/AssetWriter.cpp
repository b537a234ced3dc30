// Encodes collider assets (fp32 or fp16 samples) and writes them atomically.
#include <algorithm>
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

using detail::storeLE;

std::string str(std::uint64_t v) {
    return std::to_string(v);
}

// The volume maps as the reader accepts them: at most kMaxVolumeMaps of at most
// kMaxVolumeMapPoints, supports finite, > 0 and apart, one finite value per map point.
Result<void> checkVolumeMaps(const ColliderAsset& asset) {
    auto bad = [](ErrorCode code, const std::string& what) {
        return fail(code, "cannot write collider asset: " + what);
    };
    const std::vector<VolumeMap>& maps = asset.volumeMaps;
    if (maps.empty())
        return {};
    if (maps.size() > kMaxVolumeMaps)
        return bad(ErrorCode::InvalidArgument,
                   str(maps.size()) + " volume maps, more than " + str(kMaxVolumeMaps));
    const std::uint64_t points = volumeMapPoints(asset);
    if (points > kMaxVolumeMapPoints)
        return bad(ErrorCode::SizeOverflow, "a volume map of " + str(points) +
                                                " points exceeds the limit of " +
                                                str(kMaxVolumeMapPoints));
    for (std::size_t m = 0; m < maps.size(); ++m) {
        const double s = maps[m].support;
        if (!std::isfinite(s) || !(s > 0.0))
            return bad(ErrorCode::InvalidArgument,
                       "volume map " + str(m) + " has support " + std::to_string(s));
        for (std::size_t o = 0; o < m; ++o)
            if (std::abs(maps[o].support - s) <= kVolumeMapSupportTolerance * s)
                return bad(ErrorCode::InvalidArgument,
                           "volume maps " + str(o) + " and " + str(m) + " have the same support");
        if (maps[m].values.size() != points)
            return bad(ErrorCode::InvalidArgument, "volume map " + str(m) + " has " +
                                                       str(maps[m].values.size()) + " values for " +
                                                       str(points) + " points");
        for (std::size_t n = 0; n < maps[m].values.size(); ++n)
            if (!std::isfinite(maps[m].values[n]))
                return bad(ErrorCode::NonFinite,
                           "volume map " + str(m) + " point " + str(n) + " is not finite");
    }
    return {};
}

// The writer refuses what the reader would reject, so every file it writes loads again.
Result<void> checkWritable(const ColliderAsset& asset) {
    const ColliderMeta& m = asset.meta;
    auto bad = [](ErrorCode code, const std::string& what) {
        return fail(code, "cannot write collider asset: " + what);
    };
    if (m.dims.x < 2 || m.dims.y < 2 || m.dims.z < 2)
        return bad(ErrorCode::InvalidArgument, "grid dims " + str(m.dims.x) + "x" + str(m.dims.y) +
                                                   "x" + str(m.dims.z) + " (each must be >= 2)");
    if (m.layout == Layout::Sparse) {
        if (m.storage != Storage::F32 || !asset.distances.empty())
            return bad(ErrorCode::InvalidArgument, "a sparse asset has f32 storage and no dense "
                                                   "samples");
        if (!std::isfinite(m.bandWidth) || !(m.bandWidth > 0.0))
            return bad(ErrorCode::InvalidArgument, "band width is not a finite value > 0");
        auto stats = checkNanoVdbGrid(asset.grid, "cannot write collider asset");
        if (!stats)
            return stats.error();
        for (int a = 0; a < 3; ++a)
            if (std::abs(stats->voxelSize[a] - m.voxelSize) > 1e-9 * m.voxelSize ||
                std::abs(stats->translation[a] - m.origin[a]) > 1e-6 * m.voxelSize)
                return bad(ErrorCode::InvalidArgument,
                           "the NanoVDB grid's transform differs from the origin and voxel size");
    } else if (!asset.grid.empty() || m.bandWidth != 0.0) {
        return bad(ErrorCode::InvalidArgument, "a dense asset has no NanoVDB grid or band width");
    }
    if (m.layout != Layout::Dense && m.layout != Layout::Sparse)
        return bad(ErrorCode::InvalidArgument, "unknown layout");
    if (m.layout == Layout::Dense && asset.pointCount() > kMaxAssetPoints)
        return bad(ErrorCode::SizeOverflow, str(asset.pointCount()) + " grid points exceed the " +
                                                "limit of " + str(kMaxAssetPoints));
    if (m.layout == Layout::Dense && asset.distances.size() != asset.pointCount())
        return bad(ErrorCode::InvalidArgument, str(asset.distances.size()) + " distances for " +
                                                   str(asset.pointCount()) + " grid points");
    if (!std::isfinite(m.voxelSize) || !std::isfinite(m.origin.x) || !std::isfinite(m.origin.y) ||
        !std::isfinite(m.origin.z))
        return bad(ErrorCode::NonFinite, "origin or voxel size is not finite");
    const glm::dvec3 far = m.origin + glm::dvec3(m.dims - glm::uvec3(1)) * m.voxelSize;
    if (!std::isfinite(far.x) || !std::isfinite(far.y) || !std::isfinite(far.z))
        return bad(ErrorCode::NonFinite, "grid extent overflows");
    if (!(m.voxelSize > 0.0))
        return bad(ErrorCode::InvalidArgument,
                   "voxel size " + std::to_string(m.voxelSize) + " is not > 0");
    if (m.storage != Storage::F32 && m.storage != Storage::F16)
        return bad(ErrorCode::InvalidArgument, "unknown storage type");
    if (std::uint8_t(m.bake.signUsed) > std::uint8_t(SignMethod::Level))
        return bad(ErrorCode::InvalidArgument, "unknown sign method");
    if (m.signConvention != -1 && m.signConvention != 1)
        return bad(ErrorCode::InvalidArgument, "sign convention must be -1 or +1");
    for (const std::string* s :
         {&m.sourceFile, &m.sourceHash, &m.bake.backend, &m.bake.signMode, &m.toolVersion})
        if (s->size() > kAssetMaxStringBytes)
            return bad(ErrorCode::InvalidArgument,
                       "a metadata string is longer than " + str(kAssetMaxStringBytes) + " bytes");
    if (m.meshMass)
        if (Result<void> mass = detail::checkMassProperties(*m.meshMass); !mass)
            return bad(mass.error().code, mass.error().detail);
    for (std::size_t n = 0; n < asset.distances.size(); ++n)
        if (!std::isfinite(asset.distances[n]))
            return bad(ErrorCode::NonFinite,
                       "sample " + str(n) + " is " +
                           (std::isnan(asset.distances[n]) ? "NaN" : "infinite"));
    return checkVolumeMaps(asset);
}

// max |stored - exact| [world units] over all samples, measured in double.
double quantizationErrorOf(const std::vector<float>& distances, Storage storage) {
    if (storage == Storage::F32)
        return 0.0;
    double maxError = 0.0;
    for (const float d : distances) {
        const double err = std::abs(double(halfToFloat(floatToHalf(d))) - double(d));
        maxError = err > maxError ? err : maxError;
    }
    return maxError;
}

// Little-endian samples, x fastest (the order of `distances`).
void storeSamples(const std::vector<float>& distances, Storage storage, std::byte* out) {
    if (storage == Storage::F32) {
        for (std::size_t n = 0; n < distances.size(); ++n)
            storeLE(out + 4 * n, std::bit_cast<std::uint32_t>(distances[n]));
        return;
    }
    for (std::size_t n = 0; n < distances.size(); ++n)
        storeLE(out + 2 * n, floatToHalf(distances[n]));
}

// [bytes] one volume map's values.
std::uint64_t volumeMapBytes(const ColliderAsset& asset) {
    return asset.volumeMaps.empty() ? 0 : volumeMapPoints(asset) * 4;
}

} // namespace

std::uint32_t bytesPerSample(Storage storage) {
    return storage == Storage::F16 ? 2u : 4u;
}

Result<EncodedAsset> encodeAsset(const ColliderAsset& asset) {
    if (auto ok = checkWritable(asset); !ok)
        return ok.error();

    // Measured before the metadata is encoded, because the metadata carries the figure. Samples
    // read back from an fp16 file are already exact halves and measure 0, so re-writing such an
    // asset (validate --write) keeps the larger of the recorded and the measured error.
    const double quantizationError =
        asset.meta.storage == Storage::F32
            ? 0.0
            : std::max(asset.meta.quantizationError,
                       quantizationErrorOf(asset.distances, asset.meta.storage));
    ColliderMeta meta = asset.meta;
    meta.quantizationError = quantizationError;
    detail::PayloadSplit split;
    split.samplesBytes = asset.sparse() ? asset.grid.size()
                                        : asset.pointCount() * bytesPerSample(asset.meta.storage);
    for (const VolumeMap& map : asset.volumeMaps)
        split.volumeMapSupports.push_back(map.support);
    const std::vector<std::byte> metaBytes = detail::encodeMeta(meta, split);
    // The maps after the samples, each on a 16-byte boundary.
    const std::uint64_t mapBytes = volumeMapBytes(asset);
    const std::uint64_t mapStride = *detail::alignUp(mapBytes, kAssetPayloadAlignment);
    const std::uint64_t firstMap = *detail::alignUp(split.samplesBytes, kAssetPayloadAlignment);
    const std::uint64_t payloadSize =
        asset.volumeMaps.empty() ? split.samplesBytes
                                 : firstMap + (asset.volumeMaps.size() - 1) * mapStride + mapBytes;

    AssetHeader header;
    header.metaOffset = kAssetHeaderSize;
    header.metaSize = metaBytes.size();
    header.payloadOffset =
        *detail::alignUp(header.metaOffset + header.metaSize, kAssetPayloadAlignment);
    header.payloadSize = payloadSize;
    header.fileSize = header.payloadOffset + header.payloadSize;

    EncodedAsset encoded;
    encoded.quantizationError = quantizationError;
    encoded.bytes.resize(static_cast<std::size_t>(header.fileSize)); // padding stays zero
    std::memcpy(encoded.bytes.data() + header.metaOffset, metaBytes.data(), metaBytes.size());
    if (asset.sparse())
        std::memcpy(encoded.bytes.data() + header.payloadOffset, asset.grid.data(),
                    asset.grid.size());
    else
        storeSamples(asset.distances, asset.meta.storage,
                     encoded.bytes.data() + header.payloadOffset);
    for (std::size_t m = 0; m < asset.volumeMaps.size(); ++m)
        storeSamples(asset.volumeMaps[m].values, Storage::F32,
                     encoded.bytes.data() + header.payloadOffset + firstMap + m * mapStride);
    header.checksum = xxh3(std::span(encoded.bytes).subspan(kAssetHeaderSize));
    const auto headerBytes = packAssetHeader(header);
    std::memcpy(encoded.bytes.data(), headerBytes.data(), headerBytes.size());
    return encoded;
}

Result<void> writeAsset(const std::filesystem::path& path, const ColliderAsset& asset) {
    auto encoded = encodeAsset(asset);
    if (!encoded)
        return fail(encoded.error().code, path.string() + ": " + encoded.error().detail);
    return writeFileAtomic(path, encoded->bytes);
}

} // namespace sluice::format
