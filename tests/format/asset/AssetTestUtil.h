// Test helpers for collider assets: a small asset with every field set, and byte-level edits.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <ostream>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/support/Hash.h"

namespace sluice {
/// Lets GoogleTest print error codes by name.
inline void PrintTo(ErrorCode code, std::ostream* os) {
    *os << errorCodeName(code);
}
} // namespace sluice

namespace sluice::test {

using format::AssetHeader;
using format::ColliderAsset;
using format::Storage;

/// A small asset whose metadata fields all differ from their defaults; distances are a sphere of
/// radius 0.3 around the grid centre (so negative inside, positive outside), and meshMass holds
/// that ball's.
inline ColliderAsset makeAsset(glm::uvec3 dims = {3, 4, 5}, Storage storage = Storage::F32) {
    ColliderAsset a;
    format::ColliderMeta& m = a.meta;
    m.dims = dims;
    m.origin = {-0.5, 0.25, 1.75};
    m.voxelSize = 0.125;
    m.storage = storage;
    m.signConvention = -1;
    m.sourceFile = "bunny.obj";
    m.sourceHash = "0123456789abcdef";
    m.bake = {"cgal", 96, 2.5, "winding", format::SignMethod::Winding, 0.01};
    m.toolVersion = "sluice-bake 0.1.0";
    m.mesh = {1000, 502, 3, 7, 1, false, true};
    m.validation = {true, 4096, 0.04, 0.01, 0.015, 2, 0.99, 1.2, 0.003};
    m.quantizationError = 0.0;
    const glm::dvec3 centre = m.origin + glm::dvec3(dims - glm::uvec3(1)) * m.voxelSize * 0.5;
    // The ball's mass properties, its tensor tilted by distinct off-diagonal terms so that every
    // element differs from the others.
    format::MassProperties mass;
    mass.volume = 4.0 / 3.0 * std::numbers::pi * 0.3 * 0.3 * 0.3;
    mass.centerOfMass = centre;
    mass.inertia = glm::dmat3(0.4 * mass.volume * 0.09);
    mass.inertia[1][0] = mass.inertia[0][1] = 1.0e-5;
    mass.inertia[2][1] = mass.inertia[1][2] = -2.0e-5;
    mass.inertia[0][2] = mass.inertia[2][0] = 3.0e-5;
    m.meshMass = mass;
    a.distances.resize(a.pointCount());
    for (std::uint32_t k = 0; k < dims.z; ++k)
        for (std::uint32_t j = 0; j < dims.y; ++j)
            for (std::uint32_t i = 0; i < dims.x; ++i) {
                const glm::dvec3 d = a.pointPosition(i, j, k) - centre;
                a.distances[a.index(i, j, k)] =
                    float(std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) - 0.3);
            }
    return a;
}

/// encodeAsset that must succeed.
inline std::vector<std::byte> encodeOk(const ColliderAsset& asset) {
    auto encoded = format::encodeAsset(asset);
    if (!encoded) {
        ADD_FAILURE() << encoded.error().message();
        return {};
    }
    return std::move(encoded->bytes);
}

/// The header of an encoded file.
inline AssetHeader headerOf(std::span<const std::byte> bytes) {
    return format::unpackAssetHeader(bytes.first<format::kAssetHeaderSize>());
}

/// Overwrites the header of an encoded file.
inline void putHeader(std::vector<std::byte>& bytes, const AssetHeader& header) {
    const auto packed = format::packAssetHeader(header);
    std::memcpy(bytes.data(), packed.data(), packed.size());
}

/// Stores the checksum of the bytes after the header, as a writer would: used after editing
/// the body on purpose, so the edit reaches the checks after the checksum.
inline void reseal(std::vector<std::byte>& bytes) {
    AssetHeader h = headerOf(bytes);
    h.checksum = format::xxh3(std::span(bytes).subspan(format::kAssetHeaderSize));
    putHeader(bytes, h);
}

/// Writes `value` little-endian at `offset`.
template <class T> void poke(std::vector<std::byte>& bytes, std::size_t offset, T value) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T)); // tests run on little-endian hosts (x86-64, arm64)
    std::memcpy(bytes.data() + offset, raw, sizeof(T));
}

/// Reads a little-endian value at `offset`.
template <class T> T peek(std::span<const std::byte> bytes, std::size_t offset) {
    T value{};
    std::memcpy(&value, bytes.data() + offset, sizeof(T));
    return value;
}

/// Offset of the metadata block's byte `metaByte` in the file.
inline std::size_t metaAt(std::span<const std::byte> bytes, std::size_t metaByte) {
    return std::size_t(headerOf(bytes).metaOffset) + metaByte;
}

/// Builds a file from a metadata block and a payload with a correct header (layout, sizes,
/// checksum): used to make files that pass every header check but carry bad contents.
inline std::vector<std::byte> assemble(std::span<const std::byte> meta,
                                       std::span<const std::byte> payload) {
    AssetHeader h;
    h.metaOffset = format::kAssetHeaderSize;
    h.metaSize = meta.size();
    const std::uint64_t metaEnd = h.metaOffset + h.metaSize;
    h.payloadOffset =
        (metaEnd + format::kAssetPayloadAlignment - 1) & ~(format::kAssetPayloadAlignment - 1);
    h.payloadSize = payload.size();
    h.fileSize = h.payloadOffset + h.payloadSize;
    std::vector<std::byte> bytes(h.fileSize);
    std::memcpy(bytes.data() + h.metaOffset, meta.data(), meta.size());
    std::memcpy(bytes.data() + h.payloadOffset, payload.data(), payload.size());
    putHeader(bytes, h);
    reseal(bytes);
    return bytes;
}

/// The metadata block of an encoded file.
inline std::span<const std::byte> metaOf(std::span<const std::byte> bytes) {
    const AssetHeader h = headerOf(bytes);
    return bytes.subspan(h.metaOffset, h.metaSize);
}

/// The payload of an encoded file.
inline std::span<const std::byte> payloadOf(std::span<const std::byte> bytes) {
    const AssetHeader h = headerOf(bytes);
    return bytes.subspan(h.payloadOffset, h.payloadSize);
}

/// Code of a decode that must fail; fails the test (and returns Io) if it succeeded.
inline ErrorCode decodeError(std::span<const std::byte> bytes) {
    auto r = format::decodeAsset(bytes, "test.sdf");
    if (r.ok()) {
        ADD_FAILURE() << "decodeAsset accepted a file it should reject";
        return ErrorCode::Io;
    }
    return r.error().code;
}

} // namespace sluice::test
