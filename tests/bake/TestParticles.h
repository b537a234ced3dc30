// Particle frames for the `surface` tests: lattice balls written as PLY files, as sluice-play
// writes them (binary little-endian x y z vx vy vz id) or with a per-vertex radius.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sluice::testparticles {

/// The points of a cubic lattice of `spacing` (one point at `centre`) within `radius` of it.
inline std::vector<glm::dvec3> latticeBall(const glm::dvec3& centre, double radius,
                                           double spacing) {
    std::vector<glm::dvec3> points;
    const int n = int(std::ceil(radius / spacing));
    for (int k = -n; k <= n; ++k)
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i) {
                const glm::dvec3 offset = glm::dvec3(i, j, k) * spacing;
                // A hair of slack keeps the lattice points on the sphere (0.1 = 5 x 0.02).
                if (std::sqrt(offset.x * offset.x + offset.y * offset.y + offset.z * offset.z) <=
                    radius * (1.0 + 1e-9))
                    points.push_back(centre + offset);
            }
    return points;
}

/// The points of a lattice block: `counts` points of `spacing` along each axis from `corner`.
inline std::vector<glm::dvec3> latticeBlock(const glm::dvec3& corner, int counts, double spacing) {
    std::vector<glm::dvec3> points;
    for (int k = 0; k < counts; ++k)
        for (int j = 0; j < counts; ++j)
            for (int i = 0; i < counts; ++i)
                points.push_back(corner + glm::dvec3(i, j, k) * spacing);
    return points;
}

/// The bytes sluice-play --dump-ply writes for `points` (runtime/src/output/PlyWriter.cpp):
/// binary little-endian, float x y z vx vy vz and uint id, velocities zero; with a
/// "comment particle_radius RADIUS" line after the first comment when `radius` is not empty.
inline std::string sluicePlayPly(const std::vector<glm::dvec3>& points,
                                 const std::string& radius = "") {
    std::string bytes = "ply\nformat binary_little_endian 1.0\ncomment written by a test\n" +
                        (radius.empty() ? "" : "comment particle_radius " + radius + "\n") +
                        "element vertex " + std::to_string(points.size()) +
                        "\nproperty float x\nproperty float y\nproperty float z\n"
                        "property float vx\nproperty float vy\nproperty float vz\n"
                        "property uint id\nend_header\n";
    for (std::size_t n = 0; n < points.size(); ++n) {
        const float values[6] = {
            float(points[n].x), float(points[n].y), float(points[n].z), 0, 0, 0};
        const auto id = std::uint32_t(n);
        bytes.append(reinterpret_cast<const char*>(values), sizeof values);
        bytes.append(reinterpret_cast<const char*>(&id), sizeof id);
    }
    return bytes;
}

/// An ASCII PLY of `points` with a per-vertex "radius" (and a face element declared before the
/// vertices with no instances, which the reader skips).
inline std::string asciiPlyWithRadius(const std::vector<glm::dvec3>& points,
                                      const std::vector<double>& radii) {
    std::string text = "ply\nformat ascii 1.0\nelement face 0\n"
                       "property list uchar int vertex_indices\nelement vertex " +
                       std::to_string(points.size()) +
                       "\nproperty double x\nproperty double y\nproperty double z\n"
                       "property float radius\nend_header\n";
    char line[160];
    for (std::size_t n = 0; n < points.size(); ++n) {
        std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.9g\n", points[n].x, points[n].y,
                      points[n].z, radii[n]);
        text += line;
    }
    return text;
}

/// Writes `bytes` to `path` as they are.
inline void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

} // namespace sluice::testparticles
