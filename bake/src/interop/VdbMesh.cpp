// OpenVDB level sets as meshes: the zero isosurface of a grid, welded and oriented outward.
#include "interop/VdbMesh.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "sluice/format/support/Hash.h"

namespace fs = std::filesystem;

namespace sluice::bake {
namespace {

// Welds identical positions and keeps only the points the triangles use.
TriangleSoup weldSoup(const std::vector<openvdb::Vec3s>& points,
                      const std::vector<openvdb::Vec3I>& triangles,
                      const std::vector<openvdb::Vec4I>& quads, double scale) {
    struct KeyHash {
        std::size_t operator()(const openvdb::Vec3s& p) const {
            // + 0.0f turns -0 into +0, which compares equal and so must hash equal.
            const std::array<float, 3> value{p.x() + 0.0f, p.y() + 0.0f, p.z() + 0.0f};
            std::array<std::uint32_t, 3> bits;
            std::memcpy(bits.data(), value.data(), sizeof bits);
            return (std::size_t(bits[0]) * 0x9E3779B97F4A7C15ull ^ bits[1]) *
                       0xC2B2AE3D27D4EB4Full ^
                   bits[2];
        }
    };
    std::unordered_map<openvdb::Vec3s, std::uint32_t, KeyHash> byPosition;
    std::vector<std::uint32_t> remap(points.size(), std::numeric_limits<std::uint32_t>::max());
    TriangleSoup soup;
    auto vertex = [&](openvdb::Index source) {
        std::uint32_t& slot = remap[source];
        if (slot != std::numeric_limits<std::uint32_t>::max())
            return slot;
        auto [it, inserted] =
            byPosition.try_emplace(points[source], std::uint32_t(soup.positions.size()));
        if (inserted) {
            const openvdb::Vec3s& p = points[source];
            soup.positions.emplace_back(double(p.x()) * scale, double(p.y()) * scale,
                                        double(p.z()) * scale);
        }
        slot = it->second;
        return slot;
    };
    soup.triangles.reserve(triangles.size() + 2 * quads.size());
    for (const openvdb::Vec3I& t : triangles)
        soup.triangles.emplace_back(vertex(t[0]), vertex(t[1]), vertex(t[2]));
    for (const openvdb::Vec4I& q : quads) {
        const std::uint32_t a = vertex(q[0]), b = vertex(q[1]), c = vertex(q[2]), d = vertex(q[3]);
        soup.triangles.emplace_back(a, b, c);
        soup.triangles.emplace_back(a, c, d);
    }
    return soup;
}

// Six times the signed volume enclosed by the soup (divergence theorem).
double signedVolume6(const TriangleSoup& soup) {
    double sum = 0.0;
    for (const glm::uvec3& t : soup.triangles) {
        const glm::dvec3& a = soup.positions[t.x];
        const glm::dvec3& b = soup.positions[t.y];
        const glm::dvec3& c = soup.positions[t.z];
        sum += a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) +
               a.z * (b.x * c.y - b.y * c.x);
    }
    return sum;
}

} // namespace

Result<ImportedMesh> detail::meshLevelSet(const openvdb::FloatGrid& grid, const fs::path& path,
                                          double scale) {
    if (!std::isfinite(scale) || scale <= 0.0)
        return fail(ErrorCode::InvalidArgument, "scale must be finite and > 0");
    if (grid.activeVoxelCount() == 0)
        return fail(ErrorCode::EmptyMesh,
                    quoted(path) + ": grid '" + grid.getName() + "' has no active voxels");

    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    try {
        // Isovalue 0, adaptivity 0: the full-resolution zero isosurface, in world space.
        openvdb::tools::volumeToMesh(grid, points, triangles, quads, 0.0, 0.0);
    } catch (const std::exception& e) {
        return fail(ErrorCode::MeshImport,
                    "cannot extract the zero isosurface of " + quoted(path) + ": " + e.what());
    }
    for (const openvdb::Vec3s& p : points)
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
            return fail(ErrorCode::NonFinite,
                        quoted(path) + ": the zero isosurface has non-finite points");

    ImportedMesh mesh;
    mesh.soup = weldSoup(points, triangles, quads, scale);
    if (mesh.soup.triangles.empty())
        return fail(ErrorCode::EmptyMesh, quoted(path) + ": grid '" + grid.getName() +
                                              "' has no zero crossing, so no surface to bake");
    // Outward-facing triangles, so the winding number is +1 inside; volumeToMesh's winding
    // depends on the sign convention of the input grid.
    if (signedVolume6(mesh.soup) < 0.0)
        for (glm::uvec3& t : mesh.soup.triangles)
            std::swap(t.y, t.z);

    mesh.diagnostics = diagnose(mesh.soup);
    mesh.sourceFile = path.filename().string();
    auto hash = format::hashFileHex(path);
    if (!hash)
        return hash.error();
    mesh.sourceHash = *hash;
    return mesh;
}

} // namespace sluice::bake
