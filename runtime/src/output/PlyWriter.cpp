// Binary little-endian PLY: an ASCII header, then packed records (x y z vx vy vz id).
#include "sluice/rt/play/PlyWriter.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <string>

#include "sluice/format/support/AtomicFile.h"

namespace sluice::rt {

static_assert(std::endian::native == std::endian::little,
              "PLY writer assumes a little-endian host");

std::vector<std::byte> encodePly(std::span<const ParticleState> particles, float particleRadius) {
    std::vector<const ParticleState*> order;
    order.reserve(particles.size());
    for (const ParticleState& p : particles)
        order.push_back(&p);
    std::sort(order.begin(), order.end(),
              [](const ParticleState* a, const ParticleState* b) { return a->id < b->id; });

    std::string radius;
    if (particleRadius > 0.0f) {
        char line[64];
        std::snprintf(line, sizeof line, "comment particle_radius %.9g\n", particleRadius);
        radius = line;
    }
    const std::string header = "ply\n"
                               "format binary_little_endian 1.0\n"
                               "comment written by sluice-play " SLUICE_VERSION "\n" +
                               radius + "element vertex " + std::to_string(particles.size()) +
                               "\n"
                               "property float x\nproperty float y\nproperty float z\n"
                               "property float vx\nproperty float vy\nproperty float vz\n"
                               "property uint id\n"
                               "end_header\n";
    constexpr std::size_t kRecord = 6 * sizeof(float) + sizeof(std::uint32_t);
    std::vector<std::byte> bytes(header.size() + order.size() * kRecord);
    std::memcpy(bytes.data(), header.data(), header.size());
    std::byte* out = bytes.data() + header.size();
    for (const ParticleState* p : order) {
        const float values[6] = {p->position.x, p->position.y, p->position.z,
                                 p->velocity.x, p->velocity.y, p->velocity.z};
        std::memcpy(out, values, sizeof(values));
        std::memcpy(out + sizeof(values), &p->id, sizeof(p->id));
        out += kRecord;
    }
    return bytes;
}

Result<void> writePly(const std::filesystem::path& path, std::span<const ParticleState> particles,
                      float particleRadius) {
    const std::vector<std::byte> bytes = encodePly(particles, particleRadius);
    return format::writeFileAtomic(path, bytes);
}

} // namespace sluice::rt
