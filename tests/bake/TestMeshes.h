// Analytic test meshes (box, spheres, torus, open meshes), their exact SDFs, OBJ writing, and the
// geometry helpers the bake tests share.
//
// Header-only, shared by every bake test. All meshes are welded (shared vertices), oriented with
// outward counter-clockwise triangles, and come with the analytic signed distance of the shape
// they approximate plus a bound on the tessellation error, so a test can assert
// |phi_baked - phi_analytic| <= tessellationError + interpolation/quantization slack.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "AnalyticAsset.h"
#include "ProgramRun.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/bake/import/TriangleSoup.h"
#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::testmesh {

using testasset::assetFromSdf;

using bake::ImportedMesh;
using bake::TriangleSoup;

// ---------------------------------------------------------------------------------------------
// Geometry helpers

/// Frobenius norm of a 3x3 matrix: how the mass tests compare inertia tensors.
inline double frobenius(const glm::dmat3& m) {
    double sum = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            sum += m[c][r] * m[c][r];
    return std::sqrt(sum);
}

/// Exact distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
inline double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c) {
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return glm::length(p - a);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return glm::length(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
        return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return glm::length(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
        return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double denom = 1.0 / (va + vb + vc);
    return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

/// Brute-force unsigned distance from p to the soup (every triangle; for small test meshes).
inline double bruteForceDistance(const TriangleSoup& soup, const glm::dvec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const glm::uvec3& t : soup.triangles)
        best = std::min(best, pointTriangleDistance(p, soup.positions[t.x], soup.positions[t.y],
                                                    soup.positions[t.z]));
    return best;
}

/// Signed volume enclosed by the soup (positive when oriented outward).
inline double signedVolume(const TriangleSoup& soup) {
    double v = 0.0;
    for (const glm::uvec3& t : soup.triangles)
        v += glm::dot(soup.positions[t.x], glm::cross(soup.positions[t.y], soup.positions[t.z])) /
             6.0;
    return v;
}

// ---------------------------------------------------------------------------------------------
// Analytic signed distances (negative inside)

using testasset::boxSdf;
using testasset::sphereSdf;

/// Torus around the z axis through `center`: major radius R (to the tube centre), minor r.
inline double torusSdf(const glm::dvec3& p, const glm::dvec3& center, double majorRadius,
                       double minorRadius) {
    const glm::dvec3 d = p - center;
    const double ring = std::sqrt(d.x * d.x + d.y * d.y) - majorRadius;
    return std::sqrt(ring * ring + d.z * d.z) - minorRadius;
}

// ---------------------------------------------------------------------------------------------
// Meshes

/// Axis-aligned box [lo, hi]: 8 vertices, 12 outward triangles. With `withoutTop` the +z face
/// is left out: an open box (10 triangles, 4 boundary edges around the hole).
inline TriangleSoup boxSoup(const glm::dvec3& lo, const glm::dvec3& hi, bool withoutTop = false) {
    TriangleSoup soup;
    for (int i = 0; i < 8; ++i) // vertex i: x from bit 0, y from bit 1, z from bit 2
        soup.positions.push_back(
            {(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    soup.triangles = {{0, 4, 6}, {0, 6, 2},  // -x
                      {1, 3, 7}, {1, 7, 5},  // +x
                      {0, 1, 5}, {0, 5, 4},  // -y
                      {2, 6, 7}, {2, 7, 3},  // +y
                      {0, 2, 3}, {0, 3, 1}}; // -z
    if (!withoutTop) {
        soup.triangles.push_back({4, 5, 7}); // +z
        soup.triangles.push_back({4, 7, 6});
    }
    return soup;
}

/// Icosphere: the icosahedron subdivided `subdivisions` times (20 * 4^s triangles), vertices
/// projected onto the sphere, every triangle oriented outward.
inline TriangleSoup icoSphereSoup(const glm::dvec3& center, double radius, int subdivisions) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<glm::dvec3> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (glm::dvec3& v : unit)
        v = glm::normalize(v);
    std::vector<glm::uvec3> tris = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<unsigned, unsigned>, unsigned> midpoints;
        auto midpoint = [&](unsigned a, unsigned b) {
            const auto key = std::minmax(a, b);
            auto it = midpoints.find(key);
            if (it != midpoints.end())
                return it->second;
            unit.push_back(glm::normalize(unit[a] + unit[b]));
            const unsigned index = unsigned(unit.size() - 1);
            midpoints.emplace(key, index);
            return index;
        };
        std::vector<glm::uvec3> next;
        next.reserve(tris.size() * 4);
        for (const glm::uvec3& tri : tris) {
            const unsigned ab = midpoint(tri.x, tri.y), bc = midpoint(tri.y, tri.z),
                           ca = midpoint(tri.z, tri.x);
            next.push_back({tri.x, ab, ca});
            next.push_back({tri.y, bc, ab});
            next.push_back({tri.z, ca, bc});
            next.push_back({ab, bc, ca});
        }
        tris = std::move(next);
    }
    TriangleSoup soup;
    for (const glm::dvec3& v : unit)
        soup.positions.push_back(center + radius * v);
    for (glm::uvec3& tri : tris) { // orient outward (the sphere is convex, so this is exact)
        const glm::dvec3 n = glm::cross(unit[tri.y] - unit[tri.x], unit[tri.z] - unit[tri.x]);
        if (glm::dot(n, unit[tri.x] + unit[tri.y] + unit[tri.z]) < 0)
            std::swap(tri.y, tri.z);
    }
    soup.triangles = std::move(tris);
    return soup;
}

/// UV sphere with `slices` meridians and `stacks` bands (poles are single vertices). With
/// `upperHalfOnly` only the bands with z >= center.z are made: an open hemisphere (needs an even
/// `stacks`) whose rim, the equator, has `slices` boundary edges.
inline TriangleSoup uvSphereSoup(const glm::dvec3& center, double radius, int slices, int stacks,
                                 bool upperHalfOnly = false) {
    TriangleSoup soup;
    const double pi = std::numbers::pi;
    const int lastRing = upperHalfOnly ? stacks / 2 : stacks - 1; // rings 1 .. lastRing
    soup.positions.push_back(center + glm::dvec3(0, 0, radius));  // north pole, index 0
    for (int ring = 1; ring <= lastRing; ++ring) {
        const double polar = pi * ring / stacks;
        for (int s = 0; s < slices; ++s) {
            const double azimuth = 2.0 * pi * s / slices;
            soup.positions.push_back(
                center + radius * glm::dvec3(std::sin(polar) * std::cos(azimuth),
                                             std::sin(polar) * std::sin(azimuth), std::cos(polar)));
        }
    }
    auto at = [&](int ring, int s) { return unsigned(1 + (ring - 1) * slices + (s % slices)); };
    for (int s = 0; s < slices; ++s)
        soup.triangles.push_back({0, at(1, s), at(1, s + 1)});
    for (int ring = 1; ring < lastRing; ++ring)
        for (int s = 0; s < slices; ++s) {
            soup.triangles.push_back({at(ring, s), at(ring + 1, s), at(ring + 1, s + 1)});
            soup.triangles.push_back({at(ring, s), at(ring + 1, s + 1), at(ring, s + 1)});
        }
    if (!upperHalfOnly) {
        soup.positions.push_back(center - glm::dvec3(0, 0, radius)); // south pole
        const unsigned south = unsigned(soup.positions.size() - 1);
        for (int s = 0; s < slices; ++s)
            soup.triangles.push_back({at(lastRing, s), south, at(lastRing, s + 1)});
    }
    return soup;
}

/// Capsule along the y axis: a cylinder of radius `radius` from y = -halfAxis to +halfAxis closed
/// by two half spheres, `slices` meridians and `stacks` bands of the sphere (even), its equator
/// ring doubled at both ends of the cylinder. The largest gap to the true capsule is that of a
/// uvSphereSoup of the same slices and stacks.
inline TriangleSoup capsuleSoup(double radius, double halfAxis, int slices, int stacks) {
    TriangleSoup soup;
    const double pi = std::numbers::pi;
    // Rings from the top pole down: the upper cap's on +halfAxis, the lower cap's on -halfAxis.
    std::vector<std::pair<double, double>> rings; // (polar angle, y offset)
    for (int ring = 1; ring <= stacks / 2; ++ring)
        rings.push_back({pi * ring / stacks, halfAxis});
    for (int ring = stacks / 2; ring < stacks; ++ring)
        rings.push_back({pi * ring / stacks, -halfAxis});
    // uvSphereSoup's vertices with their axes turned (x, y, z) -> (y, z, x), a rotation, so its
    // outward winding holds.
    soup.positions.push_back({0.0, radius + halfAxis, 0.0});
    for (const auto& [polar, offset] : rings)
        for (int s = 0; s < slices; ++s) {
            const double azimuth = 2.0 * pi * s / slices;
            soup.positions.push_back({radius * std::sin(polar) * std::sin(azimuth),
                                      offset + radius * std::cos(polar),
                                      radius * std::sin(polar) * std::cos(azimuth)});
        }
    const int last = int(rings.size());
    auto at = [&](int ring, int s) { return unsigned(1 + (ring - 1) * slices + (s % slices)); };
    for (int s = 0; s < slices; ++s)
        soup.triangles.push_back({0, at(1, s), at(1, s + 1)});
    for (int ring = 1; ring < last; ++ring)
        for (int s = 0; s < slices; ++s) {
            soup.triangles.push_back({at(ring, s), at(ring + 1, s), at(ring + 1, s + 1)});
            soup.triangles.push_back({at(ring, s), at(ring + 1, s + 1), at(ring, s + 1)});
        }
    soup.positions.push_back({0.0, -radius - halfAxis, 0.0});
    const unsigned south = unsigned(soup.positions.size() - 1);
    for (int s = 0; s < slices; ++s)
        soup.triangles.push_back({at(last, s), south, at(last, s + 1)});
    return soup;
}

/// Torus around the z axis: `majorSegments` around the ring, `minorSegments` around the tube,
/// each quad (a planar isosceles trapezoid) split into two outward triangles.
inline TriangleSoup torusSoup(const glm::dvec3& center, double majorRadius, double minorRadius,
                              int majorSegments, int minorSegments) {
    TriangleSoup soup;
    const double pi = std::numbers::pi;
    for (int i = 0; i < majorSegments; ++i)
        for (int j = 0; j < minorSegments; ++j) {
            const double theta = 2.0 * pi * i / majorSegments, phi = 2.0 * pi * j / minorSegments;
            const double ring = majorRadius + minorRadius * std::cos(phi);
            soup.positions.push_back(center + glm::dvec3(ring * std::cos(theta),
                                                         ring * std::sin(theta),
                                                         minorRadius * std::sin(phi)));
        }
    auto at = [&](int i, int j) {
        return unsigned((i % majorSegments) * minorSegments + (j % minorSegments));
    };
    // d/dtheta x d/dphi points outward, so (i,j) -> (i+1,j) -> (i+1,j+1) is counter-clockwise.
    for (int i = 0; i < majorSegments; ++i)
        for (int j = 0; j < minorSegments; ++j) {
            soup.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            soup.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return soup;
}

// ---------------------------------------------------------------------------------------------
// Tessellation error bounds: the Hausdorff distance between the polygon and the true surface,
// which bounds |SDF_polygon(p) - SDF_true(p)| at every point p (both are 1-Lipschitz distance
// functions of sets that lie within that distance of each other; signs agree away from the band).

/// For a sphere whose vertices all lie on it: the polygon lies inside, and its farthest point
/// from the sphere is the point of a face nearest the centre, so the bound is
/// radius - min over faces of dist(center, face). Exact, not an estimate.
inline double sphereTessellationError(const TriangleSoup& soup, const glm::dvec3& center,
                                      double radius) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const glm::uvec3& t : soup.triangles)
        nearest =
            std::min(nearest, pointTriangleDistance(center, soup.positions[t.x],
                                                    soup.positions[t.y], soup.positions[t.z]));
    return radius - nearest;
}

/// For torusSoup: each trapezoid spans an arc of 2*pi/minorSegments around the tube and
/// 2*pi/majorSegments around the ring (ring radius at most R + r); the sagittas of the two arcs
/// add up to a bound on how far the flat trapezoid strays from the curved patch.
inline double torusTessellationError(double majorRadius, double minorRadius, int majorSegments,
                                     int minorSegments) {
    const double pi = std::numbers::pi;
    return minorRadius * (1.0 - std::cos(pi / minorSegments)) +
           (majorRadius + minorRadius) * (1.0 - std::cos(pi / majorSegments));
}

// ---------------------------------------------------------------------------------------------
// Bake inputs and files

/// Wraps a soup as if it had been imported: diagnostics from bake::diagnose, a fixed name/hash.
inline ImportedMesh imported(TriangleSoup soup, std::string name = "analytic") {
    ImportedMesh mesh;
    mesh.diagnostics = bake::diagnose(soup);
    mesh.soup = std::move(soup);
    mesh.sourceFile = std::move(name);
    mesh.sourceHash = "0000000000000000";
    return mesh;
}

/// A fresh folder for test files (tests/common/ProgramRun.h).
using testrun::tempDir;

/// Writes the soup as a Wavefront OBJ ("v x y z" with 17 significant digits, "f a b c"
/// 1-based), losing nothing on our side (assimp reads the coordinates as floats, so an import
/// gives them back to about 1e-7 relative). Returns false on I/O error.
inline bool writeObj(const TriangleSoup& soup, const std::filesystem::path& path) {
    std::ofstream out(path);
    if (!out)
        return false;
    char line[128];
    for (const glm::dvec3& v : soup.positions) {
        std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", v.x, v.y, v.z);
        out << line;
    }
    for (const glm::uvec3& t : soup.triangles)
        out << "f " << t.x + 1 << ' ' << t.y + 1 << ' ' << t.z + 1 << '\n';
    return bool(out.flush());
}

/// Writes `soup` to <test temp root>/<folder>/<fileName> and returns the path (empty on
/// failure). The folder is created if needed but, unlike tempDir, not emptied, so several files
/// can go into one folder.
inline std::filesystem::path writeTempObj(const TriangleSoup& soup, const std::string& folder,
                                          const std::string& fileName) {
#ifdef SLUICE_TEST_TMP
    const std::filesystem::path dir = std::filesystem::path(SLUICE_TEST_TMP) / folder;
#else
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / "sluice-tests" / folder;
#endif
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    const std::filesystem::path path = dir / fileName;
    return writeObj(soup, path) ? path : std::filesystem::path{};
}

} // namespace sluice::testmesh
