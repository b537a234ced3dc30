// The surface mesh as a binary little-endian PLY.
#include <bit>
#include <cstring>
#include <string>

#include "sluice/format/support/AtomicFile.h"
#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::rt {

static_assert(std::endian::native == std::endian::little,
              "PLY writer assumes a little-endian host");

Result<void> writeSurfacePly(const std::filesystem::path& path, const SurfaceMesh& mesh) {
    const std::string header = "ply\n"
                               "format binary_little_endian 1.0\n"
                               "comment fluid surface written by sluice-play " SLUICE_VERSION "\n"
                               "element vertex " +
                               std::to_string(mesh.vertices.size()) +
                               "\n"
                               "property float x\nproperty float y\nproperty float z\n"
                               "property float nx\nproperty float ny\nproperty float nz\n"
                               "element face " +
                               std::to_string(mesh.triangles.size()) +
                               "\n"
                               "property list uchar uint vertex_indices\n"
                               "end_header\n";
    constexpr std::size_t kVertex = 6 * sizeof(float);
    constexpr std::size_t kFace = 1 + 3 * sizeof(std::uint32_t);
    std::vector<std::byte> bytes(header.size() + mesh.vertices.size() * kVertex +
                                 mesh.triangles.size() * kFace);
    std::memcpy(bytes.data(), header.data(), header.size());
    std::byte* out = bytes.data() + header.size();
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        const glm::vec3& p = mesh.vertices[i];
        const glm::vec3& n = mesh.normals[i];
        const float values[6] = {p.x, p.y, p.z, n.x, n.y, n.z};
        std::memcpy(out, values, sizeof values);
        out += kVertex;
    }
    for (const glm::uvec3& t : mesh.triangles) {
        *out = std::byte{3};
        const std::uint32_t indices[3] = {t.x, t.y, t.z};
        std::memcpy(out + 1, indices, sizeof indices);
        out += kFace;
    }
    return format::writeFileAtomic(path, bytes);
}

} // namespace sluice::rt
