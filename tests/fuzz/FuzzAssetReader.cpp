// libFuzzer target: the collider asset reader (decodeAsset) on untrusted bytes.
//
// Each input is decoded twice: as it is, and with its checksum repaired, so that mutations get
// past the checksum to the metadata and payload decoders. An accepted asset must satisfy what
// AssetIO.h promises (a sparse one a validated NanoVDB grid), re-encode to bytes that decode to
// the same asset, and sample finitely;
// no single allocation may exceed what the input's size justifies.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "FuzzSupport.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/NanoVdbCheck.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/format/support/Hash.h"

namespace {

using namespace sluice;
using namespace sluice::format;

constexpr const char* kName = "fuzz/input.slc";

/// [bytes] the most a decode may allocate at once for `size` input bytes: fp16 samples become
/// floats (twice the payload), strings and messages are bounded by the metadata block.
std::size_t allocationLimit(std::size_t size) {
    return 2 * size + (std::size_t(64) << 10);
}

void checkAccepted(const ColliderAsset& asset, std::span<const std::byte> bytes) {
    const ColliderMeta& m = asset.meta;
    SLUICE_FUZZ_CHECK(m.dims.x >= 2 && m.dims.y >= 2 && m.dims.z >= 2, "dims >= 2");
    if (asset.sparse()) {
        SLUICE_FUZZ_CHECK(asset.distances.empty(), "no dense samples in a sparse asset");
        SLUICE_FUZZ_CHECK(checkNanoVdbGrid(asset.grid, kName).ok(), "the grid was validated");
        SLUICE_FUZZ_CHECK(asset.grid.size() <= bytes.size(), "the file holds the grid");
    } else {
        SLUICE_FUZZ_CHECK(asset.pointCount() <= kMaxAssetPoints, "point limit");
        SLUICE_FUZZ_CHECK(asset.distances.size() == asset.pointCount(), "one sample per point");
        SLUICE_FUZZ_CHECK(asset.pointCount() * bytesPerSample(m.storage) <= bytes.size(),
                          "the file holds every sample");
    }
    SLUICE_FUZZ_CHECK(std::isfinite(m.voxelSize) && m.voxelSize > 0.0, "voxel size");
    for (int a = 0; a < 3; ++a) {
        SLUICE_FUZZ_CHECK(std::isfinite(m.origin[a]), "origin finite");
        SLUICE_FUZZ_CHECK(std::isfinite(m.origin[a] + (m.dims[a] - 1.0) * m.voxelSize),
                          "far corner finite");
    }
    for (float d : asset.distances)
        SLUICE_FUZZ_CHECK(std::isfinite(d), "samples finite");

    // A consumer samples it: values stay finite inside the grid, nothing crashes around it.
    const SdfSampler sampler(asset);
    const glm::dvec3 lo = m.origin;
    const glm::dvec3 hi = sampler.boxMax();
    for (const double t : {-0.25, 0.0, 0.37, 1.0, 1.5}) {
        const glm::dvec3 p = lo + (hi - lo) * t;
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            continue; // beyond the double range outside a huge grid: not a query anyone makes
        const float v = sampler.value(p);
        (void)sampler.gradient(p); // may overflow for hostile spacings; must not crash
        if (t >= 0.0 && t <= 1.0)
            SLUICE_FUZZ_CHECK(std::isfinite(v), "sampled value finite inside the grid");
    }

    // Round trip: what the reader accepts, the writer writes back, and it reads the same.
    Result<EncodedAsset> encoded = encodeAsset(asset);
    if (!encoded)
        fuzz::violated("an accepted asset re-encodes", encoded.error().message().c_str());
    Result<ColliderAsset> again = decodeAsset(encoded->bytes, kName);
    if (!again)
        fuzz::violated("a re-encoded asset decodes", again.error().message().c_str());
    SLUICE_FUZZ_CHECK(again->meta.dims == m.dims, "round trip keeps dims");
    SLUICE_FUZZ_CHECK(again->meta.sourceFile == m.sourceFile, "round trip keeps strings");
    SLUICE_FUZZ_CHECK(again->meta.meshMass.has_value() == m.meshMass.has_value() &&
                          (!m.meshMass || (again->meta.meshMass->volume == m.meshMass->volume &&
                                           again->meta.meshMass->inertia == m.meshMass->inertia)),
                      "round trip keeps the mass properties");
    SLUICE_FUZZ_CHECK(again->distances.size() == asset.distances.size(), "round trip size");
    SLUICE_FUZZ_CHECK(again->grid == asset.grid, "round trip keeps the NanoVDB grid");
    SLUICE_FUZZ_CHECK(asset.distances.empty() ||
                          std::memcmp(again->distances.data(), asset.distances.data(),
                                      asset.distances.size() * sizeof(float)) == 0,
                      "round trip keeps every sample bit for bit");
}

void decodeChecked(std::span<const std::byte> bytes) {
    ColliderAsset accepted;
    bool ok = false;
    {
        fuzz::AllocationWatch watch;
        Result<ColliderAsset> r = decodeAsset(bytes, kName);
        watch.check(allocationLimit(bytes.size()), "decodeAsset");
        ok = fuzz::takeResult(r, accepted, kName);
        SLUICE_FUZZ_CHECK(ok || r.error().code != ErrorCode::Io,
                          "no Io error from bytes in memory");
    }
    if (ok)
        checkAccepted(accepted, bytes);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // The repaired copy carries its own checksum, so the reader goes on to the metadata.
    return fuzz::checkAsIsAndRepaired(data, size, decodeChecked, [](std::vector<std::byte>& b) {
        if (b.size() <= kAssetHeaderSize)
            return false;
        const std::uint64_t sum = xxh3(std::span(b).subspan(kAssetHeaderSize));
        for (int i = 0; i < 8; ++i) // little-endian, as AssetHeader.h draws it
            b[header_offset::kChecksum + i] = std::byte((sum >> (8 * i)) & 0xFF);
        return true;
    });
}
