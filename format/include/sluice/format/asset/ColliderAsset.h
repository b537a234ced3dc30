// The collider asset in memory: a dense or sparse (NanoVDB) signed distance grid plus provenance.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace sluice::format {

/// How distances are stored in the file. In memory they are always float.
enum class Storage : std::uint8_t {
    F32 = 0, ///< IEEE binary32
    F16 = 1, ///< IEEE binary16; the quantization error is recorded in the metadata
};

/// How the samples are laid out (format 1.2 on; a 1.0 or 1.1 file is always Dense).
enum class Layout : std::uint8_t {
    Dense = 0,  ///< dims.x * dims.y * dims.z samples, x fastest (`distances`)
    Sparse = 1, ///< a NanoVDB float level set: a narrow band of voxels, tiles elsewhere (`grid`)
};

/// "dense" | "sparse", as the command line and JSON spell it.
inline const char* layoutName(Layout layout) {
    return layout == Layout::Sparse ? "sparse" : "dense";
}

/// Allocator aligning to 32 bytes, what NanoVDB requires of a grid buffer
/// (NANOVDB_DATA_ALIGNMENT), so the bytes can be walked in place once validated.
template <class T> struct GridAllocator {
    using value_type = T;
    static constexpr std::align_val_t kAlignment{32};
    GridAllocator() = default;
    template <class U> GridAllocator(const GridAllocator<U>&) {}
    T* allocate(std::size_t n) {
        return static_cast<T*>(::operator new(n * sizeof(T), kAlignment));
    }
    void deallocate(T* p, std::size_t) { ::operator delete(p, kAlignment); }
    template <class U> bool operator==(const GridAllocator<U>&) const { return true; }
};

/// The bytes of one NanoVDB grid, 32-byte aligned.
using GridBytes = std::vector<std::byte, GridAllocator<std::byte>>;

/// How the inside/outside sign was decided.
enum class SignMethod : std::uint8_t {
    Parity = 0,  ///< ray parity on a closed mesh (CGAL Side_of_triangle_mesh)
    Winding = 1, ///< generalized winding number > 0.5 (Jacobson et al. 2013)
    Level = 2,   ///< taken from an input level set (.vdb)
};

/// "f32" | "f16", as the command line and JSON spell it.
inline const char* storageName(Storage storage) {
    return storage == Storage::F16 ? "f16" : "f32";
}

/// "parity" | "winding" | "level", as the command line, JSON and VDB metadata spell it.
inline const char* signMethodName(SignMethod method) {
    switch (method) {
    case SignMethod::Parity: return "parity";
    case SignMethod::Winding: return "winding";
    case SignMethod::Level: return "level";
    }
    return "unknown";
}

/// Mesh diagnostics measured on the welded triangle soup at import.
struct MeshDiagnostics {
    std::uint64_t triangles = 0;           ///< after import, degenerate ones included
    std::uint64_t vertices = 0;            ///< after welding identical positions
    std::uint64_t degenerateTriangles = 0; ///< zero area or repeated vertex
    std::uint64_t boundaryEdges = 0;       ///< edges used by exactly one triangle
    std::uint64_t nonManifoldEdges = 0;    ///< edges used by three or more triangles
    bool closed = false;                   ///< no boundary edges and no non-manifold edges
    bool selfIntersecting = false;         ///< CGAL PMP found intersecting triangle pairs
};

/// The settings a bake was made with.
struct BakeParams {
    std::string backend;        ///< "cgal", "gpu", ...
    std::uint32_t resolution = 0; ///< voxels along the longest side, 0 if voxelSize was given
    double padding = 3.0;       ///< [voxels] added on every side of the mesh box
    std::string signMode = "auto"; ///< "auto" | "parity" | "winding" as requested
    SignMethod signUsed = SignMethod::Parity; ///< what was actually used
    double scale = 1.0;         ///< uniform import scale applied to the mesh
};

/// Figures from `sluice-bake validate` against the CGAL reference, when known.
struct ValidationFigures {
    bool known = false;
    std::uint64_t pointsChecked = 0;
    double maxError = 0.0;  ///< [voxels] max |phi - phi_ref|
    double meanError = 0.0; ///< [voxels]
    double rmsError = 0.0;  ///< [voxels]
    std::uint64_t signMismatches = 0;
    double eikonalMedian = 0.0;       ///< median |grad phi|
    double eikonalP99 = 0.0;          ///< 99th percentile of |grad phi|
    double eikonalOutsideShare = 0.0; ///< share of |grad phi| outside [0.5, 1.5]
};

/// The solid's volume, centre of mass and inertia tensor at unit density, in the asset's own
/// frame and units (the bake's world units, after its --scale). Scale by density to get mass
/// and inertia in kg; under a uniform placement scale s, volume grows by s^3 and inertia by s^5.
struct MassProperties {
    double volume = 0.0;          ///< [units^3], > 0 for a solid
    glm::dvec3 centerOfMass{0.0}; ///< [units], in the asset frame
    glm::dmat3 inertia{0.0};      ///< about the centre of mass, unit density [units^5]
};

/// Everything about a collider except its samples.
struct ColliderMeta {
    glm::uvec3 dims{0};       ///< [grid points] along x, y, z; each >= 2
    glm::dvec3 origin{0.0};   ///< [world units] position of grid point (0,0,0)
    double voxelSize = 0.0;   ///< [world units] spacing between grid points, > 0
    Storage storage = Storage::F32;
    std::int8_t signConvention = -1; ///< sign of phi inside the solid; always -1 for now
    std::string sourceFile;   ///< file name of the source mesh (no folders)
    std::string sourceHash;   ///< XXH3-64 of the source file bytes, 16 hex digits
    BakeParams bake;
    std::string toolVersion;  ///< "sluice-bake 0.1.0"
    MeshDiagnostics mesh;
    ValidationFigures validation;
    double quantizationError = 0.0; ///< [world units] max |stored - exact| from fp16, 0 for fp32
    /// Exact mass properties of the closed source mesh (polyhedral integrals, Mirtich 1996).
    /// Absent for open meshes, level-set inputs and assets older than format 1.1.
    std::optional<MassProperties> meshMass;
    Layout layout = Layout::Dense; ///< format 1.2 on; older files are Dense
    double bandWidth = 0.0; ///< [voxels] Sparse: half-width of the band of exact values, else 0
};

/// The boundary model's volume map of a collider for one kernel radius (docs/pbf.md, "Volume
/// maps"), baked with it so that a scene of that radius loads without building it.
struct VolumeMap {
    double support = 0.0;      ///< the kernel radius over the placement scale [asset units], > 0
    std::vector<float> values; ///< one per map point (volumeMapPoints), in that order
};

/// Relative difference within which a baked map's support is the one a scene asks for: the
/// scene's h is a float and its scale divides it, so a support written with six digits
/// (0.0266667 for 0.04 / 1.5) still matches; the map changes by about as much, far below its
/// quadrature's own error.
inline constexpr double kVolumeMapSupportTolerance = 1e-4;

/// A collider: phi sampled at origin + (i, j, k) * voxelSize, negative inside, in world units.
/// Dense: distances[i + dims.x * (j + dims.y * k)] (x fastest), `grid` empty.
/// Sparse: `grid` is one NanoVDB float level set whose index (i, j, k) is that same point; voxels
/// within meta.bandWidth voxels of the surface hold the exact distance, everything else tiles or
/// background of magnitude bandWidth * voxelSize with the right sign. `distances` is empty, and
/// dims only bound the baked region (pointCount() may exceed kMaxAssetPoints).
struct ColliderAsset {
    ColliderMeta meta;
    std::vector<float> distances;
    GridBytes grid;
    /// Volume maps baked with it (format 1.3 on): at most kMaxVolumeMaps, supports apart by
    /// more than kVolumeMapSupportTolerance.
    std::vector<VolumeMap> volumeMaps;

    /// True for a Sparse (NanoVDB) asset.
    bool sparse() const { return meta.layout == Layout::Sparse; }

    /// The baked volume map for `support` [asset units], or null when none matches.
    const VolumeMap* volumeMapFor(double support) const {
        for (const VolumeMap& map : volumeMaps)
            if (std::abs(map.support - support) <= kVolumeMapSupportTolerance * support)
                return &map;
        return nullptr;
    }
    /// Number of grid points (dims.x * dims.y * dims.z), computed in 64 bits.
    std::uint64_t pointCount() const {
        return std::uint64_t(meta.dims.x) * meta.dims.y * meta.dims.z;
    }
    /// Linear index of grid point (i, j, k).
    std::uint64_t index(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
        return i + std::uint64_t(meta.dims.x) * (j + std::uint64_t(meta.dims.y) * k);
    }
    /// World position of grid point (i, j, k).
    glm::dvec3 pointPosition(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
        return meta.origin + glm::dvec3(i, j, k) * meta.voxelSize;
    }
};

} // namespace sluice::format
