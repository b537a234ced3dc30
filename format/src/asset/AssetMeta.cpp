// Cereal (PortableBinary) encoding of ColliderMeta, with bounded reads for untrusted files.
#include "asset/AssetMeta.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <streambuf>

#include <cereal/archives/portable_binary.hpp>
#include <cereal/cereal.hpp>

#include "sluice/format/support/Assert.h"
#include "sluice/format/asset/AssetHeader.h"

namespace sluice::format::detail {

namespace {

using InArchive = cereal::PortableBinaryInputArchive;
using OutArchive = cereal::PortableBinaryOutputArchive;

// Relative to the largest element: how far apart I(i,j) and I(j,i) may be (a tensor written by
// this code is exactly symmetric; the slack is for other writers' rounding).
constexpr double kMassSymmetryTolerance = 1e-9;

// A metadata field that decoded but cannot be right; turned into BadMetadata at the boundary.
struct MetaError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Read-only stream over the metadata bytes (no copy), which also tells how much is left so a
// length read from the file can be checked before anything is allocated for it.
class SpanBuf : public std::streambuf {
public:
    explicit SpanBuf(std::span<const std::byte> bytes) {
        // setg wants char*; nothing writes through it (no put area, no putback overrides).
        char* begin = const_cast<char*>(reinterpret_cast<const char*>(bytes.data()));
        setg(begin, begin, begin + bytes.size());
    }
    std::uint64_t remaining() const { return std::uint64_t(egptr() - gptr()); }
};

// Strings: cereal's own std::string loader resizes to the length in the stream before reading,
// so a hostile length would allocate first and fail later. Here the length is bounded by the
// bytes actually left and by kAssetMaxStringBytes before the resize.
void saveString(OutArchive& ar, const std::string& s) {
    SLUICE_ASSERT(s.size() <= kAssetMaxStringBytes, "metadata string over the limit");
    ar(cereal::make_size_tag(static_cast<cereal::size_type>(s.size())));
    if (!s.empty())
        ar(cereal::binary_data(s.data(), s.size()));
}

void loadString(InArchive& ar, const SpanBuf& buf, std::string& s, const char* field) {
    cereal::size_type size = 0;
    ar(cereal::make_size_tag(size));
    if (size > kAssetMaxStringBytes || size > buf.remaining())
        throw MetaError(std::string(field) + " claims " + std::to_string(size) +
                        " bytes but only " + std::to_string(buf.remaining()) + " remain (limit " +
                        std::to_string(kAssetMaxStringBytes) + ")");
    s.resize(std::size_t(size));
    if (size > 0)
        ar(cereal::binary_data(s.data(), std::size_t(size)));
}

// Booleans travel as one byte, 0 or 1; anything else would be an invalid bool representation.
void saveBool(OutArchive& ar, bool b) {
    ar(std::uint8_t(b ? 1 : 0));
}

void loadBool(InArchive& ar, bool& b, const char* field) {
    std::uint8_t v = 0;
    ar(v);
    if (v > 1)
        throw MetaError(std::string(field) + " is " + std::to_string(v) + ", not 0 or 1");
    b = v == 1;
}

// Enums travel as their underlying byte and are range-checked against the last enumerator.
template <class E> void loadEnum(InArchive& ar, E& e, E last, const char* field) {
    std::uint8_t v = 0;
    ar(v);
    if (v > std::uint8_t(last))
        throw MetaError(std::string(field) + " has unknown value " + std::to_string(v));
    e = E(v);
}

// Mass properties (1.1): a presence byte, then volume, centre of mass and the inertia tensor
// row by row, 13 doubles. Their values are judged by checkMassProperties, not here.
void saveMass(OutArchive& ar, const std::optional<MassProperties>& mass) {
    saveBool(ar, mass.has_value());
    if (!mass)
        return;
    ar(mass->volume, mass->centerOfMass.x, mass->centerOfMass.y, mass->centerOfMass.z);
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
            ar(mass->inertia[col][row]); // glm is column-major: [col][row]
}

void loadMass(InArchive& ar, std::optional<MassProperties>& mass) {
    bool present = false;
    loadBool(ar, present, "meshMass presence flag");
    if (!present)
        return;
    MassProperties m;
    ar(m.volume, m.centerOfMass.x, m.centerOfMass.y, m.centerOfMass.z);
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
            ar(m.inertia[col][row]);
    mass = m;
}

// The field order below IS the file format; AssetHeader.h draws its start. Version 1.0 ends
// with quantizationError. A later minor version appends fields at the end, read only when the
// header's minor >= that minor: 1.1 appends meshMass, 1.2 the layout and band width, 1.3 the
// payload's split (saveSplit).
void save(OutArchive& ar, const ColliderMeta& m) {
    ar(m.dims.x, m.dims.y, m.dims.z);
    ar(m.origin.x, m.origin.y, m.origin.z);
    ar(m.voxelSize);
    ar(std::uint8_t(m.storage), m.signConvention);
    saveString(ar, m.sourceFile);
    saveString(ar, m.sourceHash);

    saveString(ar, m.bake.backend);
    ar(m.bake.resolution, m.bake.padding);
    saveString(ar, m.bake.signMode);
    ar(std::uint8_t(m.bake.signUsed), m.bake.scale);

    saveString(ar, m.toolVersion);

    ar(m.mesh.triangles, m.mesh.vertices, m.mesh.degenerateTriangles, m.mesh.boundaryEdges,
       m.mesh.nonManifoldEdges);
    saveBool(ar, m.mesh.closed);
    saveBool(ar, m.mesh.selfIntersecting);

    const ValidationFigures& v = m.validation;
    saveBool(ar, v.known);
    ar(v.pointsChecked, v.maxError, v.meanError, v.rmsError, v.signMismatches);
    ar(v.eikonalMedian, v.eikonalP99, v.eikonalOutsideShare);

    ar(m.quantizationError);

    saveMass(ar, m.meshMass); // 1.1 (kAssetMinorMeshMass)

    ar(std::uint8_t(m.layout), m.bandWidth); // 1.2 (kAssetMinorSparse)
}

// 1.3 (kAssetMinorVolumeMaps): the samples' size, the map count, each map's support.
void saveSplit(OutArchive& ar, const PayloadSplit& split) {
    SLUICE_ASSERT(split.volumeMapSupports.size() <= kMaxVolumeMaps, "too many volume maps");
    ar(split.samplesBytes, std::uint32_t(split.volumeMapSupports.size()));
    for (double support : split.volumeMapSupports)
        ar(support);
}

void loadSplit(InArchive& ar, PayloadSplit& split) {
    std::uint32_t count = 0;
    ar(split.samplesBytes, count);
    if (count > kMaxVolumeMaps)
        throw MetaError("volume map count " + std::to_string(count) + " exceeds the limit of " +
                        std::to_string(kMaxVolumeMaps));
    split.volumeMapSupports.resize(count);
    for (double& support : split.volumeMapSupports)
        ar(support);
}

void load(InArchive& ar, const SpanBuf& buf, std::uint16_t minor, ColliderMeta& m) {
    ar(m.dims.x, m.dims.y, m.dims.z);
    ar(m.origin.x, m.origin.y, m.origin.z);
    ar(m.voxelSize);
    loadEnum(ar, m.storage, Storage::F16, "storage");
    ar(m.signConvention);
    loadString(ar, buf, m.sourceFile, "sourceFile");
    loadString(ar, buf, m.sourceHash, "sourceHash");

    loadString(ar, buf, m.bake.backend, "bake.backend");
    ar(m.bake.resolution, m.bake.padding);
    loadString(ar, buf, m.bake.signMode, "bake.signMode");
    loadEnum(ar, m.bake.signUsed, SignMethod::Level, "bake.signUsed");
    ar(m.bake.scale);

    loadString(ar, buf, m.toolVersion, "toolVersion");

    ar(m.mesh.triangles, m.mesh.vertices, m.mesh.degenerateTriangles, m.mesh.boundaryEdges,
       m.mesh.nonManifoldEdges);
    loadBool(ar, m.mesh.closed, "mesh.closed");
    loadBool(ar, m.mesh.selfIntersecting, "mesh.selfIntersecting");

    ValidationFigures& v = m.validation;
    loadBool(ar, v.known, "validation.known");
    ar(v.pointsChecked, v.maxError, v.meanError, v.rmsError, v.signMismatches);
    ar(v.eikonalMedian, v.eikonalP99, v.eikonalOutsideShare);

    ar(m.quantizationError);

    if (minor >= kAssetMinorMeshMass)
        loadMass(ar, m.meshMass);

    if (minor >= kAssetMinorSparse) {
        loadEnum(ar, m.layout, Layout::Sparse, "layout");
        ar(m.bandWidth);
    }
}

} // namespace

Result<void> checkMassProperties(const MassProperties& mass) {
    auto nonFinite = [](const char* field) {
        return fail(ErrorCode::NonFinite, std::string("meshMass.") + field + " is not finite");
    };
    if (!std::isfinite(mass.volume))
        return nonFinite("volume");
    if (!(mass.volume > 0.0))
        return fail(ErrorCode::InvalidArgument,
                    "meshMass.volume is " + std::to_string(mass.volume) + ", not > 0");
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(mass.centerOfMass[a]))
            return nonFinite("centerOfMass");
    double largest = 0.0;
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) {
            if (!std::isfinite(mass.inertia[col][row]))
                return nonFinite("inertia");
            largest = std::max(largest, std::abs(mass.inertia[col][row]));
        }
    for (int row = 0; row < 3; ++row)
        for (int col = row + 1; col < 3; ++col)
            if (std::abs(mass.inertia[col][row] - mass.inertia[row][col]) >
                kMassSymmetryTolerance * largest)
                return fail(ErrorCode::InvalidArgument,
                            "meshMass.inertia is not symmetric (element " + std::to_string(row) +
                                "," + std::to_string(col) + " differs from " + std::to_string(col) +
                                "," + std::to_string(row) + ")");
    return {};
}

std::vector<std::byte> encodeMeta(const ColliderMeta& meta, const PayloadSplit& split) {
    std::ostringstream os(std::ios::binary);
    {
        OutArchive ar(os, OutArchive::Options::LittleEndian());
        save(ar, meta);
        saveSplit(ar, split);
    }
    const std::string s = std::move(os).str();
    const auto* p = reinterpret_cast<const std::byte*>(s.data());
    return std::vector<std::byte>(p, p + s.size());
}

Result<DecodedMeta> decodeMeta(std::span<const std::byte> bytes, std::uint16_t minor,
                               const std::string& name) {
    auto bad = [&](const std::string& what) {
        return fail(ErrorCode::BadMetadata,
                    name + ": metadata block is invalid (" + what + "); re-bake with sluice-bake");
    };
    // cereal's first byte says the archive's endianness; we always write little-endian (1).
    // Checked here because cereal would treat any nonzero value other than 1 as "swap".
    if (bytes.empty() || std::to_integer<std::uint8_t>(bytes[0]) != 1)
        return bad("it is empty or not a little-endian archive");

    SpanBuf buf(bytes);
    std::istream is(&buf);
    DecodedMeta meta;
    try {
        InArchive ar(is, InArchive::Options::LittleEndian());
        load(ar, buf, minor, meta.meta);
        meta.hasSplit = minor >= kAssetMinorVolumeMaps;
        if (meta.hasSplit)
            loadSplit(ar, meta.split);
    } catch (const MetaError& e) {
        return bad(e.what());
    } catch (const cereal::Exception& e) {
        return bad(std::string("ends early: ") + e.what());
    } catch (const std::exception& e) {
        return bad(e.what());
    }
    if (buf.remaining() != 0)
        return bad(std::to_string(buf.remaining()) + " unexpected bytes after the last field");
    return meta;
}

} // namespace sluice::format::detail
