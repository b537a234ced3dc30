// Private: particle positions (and radii) out of a PLY point file, for `surface`.
//
// sluice-play --dump-ply writes binary little-endian files with one "vertex" element of
// float x y z vx vy vz and uint id (runtime/src/output/PlyWriter.cpp); other tools add a
// per-vertex "radius", and sluice-play records its particle radius in the header as
// "comment particle_radius R". The header goes through the same hardened reader as `bake`'s PLY
// pre-flight check (import/PlyHeader.h), asking for points instead of a mesh; the body is
// walked here with every read bounds-checked.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <optional>

#include <glm/vec3.hpp>

#include "sluice/format/support/Result.h"

namespace sluice::bake::detail {

/// [bytes] The largest particle file read (the whole file is held in memory while it is read).
inline constexpr std::uint64_t kMaxParticlePlyBytes = std::uint64_t(8) << 30;

/// The particles of one PLY file.
struct ParticleFrame {
    std::vector<glm::dvec3> positions; ///< [world units] one per vertex, all finite
    std::vector<double> radii;         ///< [world units] per vertex "radius", empty if none
    /// [world units] the header's "comment particle_radius R" (finite, > 0), if it has one.
    std::optional<double> headerRadius;
    std::string sourceHash; ///< XXH3-64 of the file's bytes, 16 hex digits
};

/// Reads the "vertex" element of a PLY file (ASCII or binary, either byte order; positions
/// and radius of any scalar type; elements before "vertex" are skipped, data after it
/// ignored). Every message names the file. Errors: Io (missing, unreadable, not a regular
/// file), SizeOverflow (over kMaxParticlePlyBytes), BadMagic (not a PLY file), MeshImport (a
/// bad header, no x/y/z, a list-valued x, y, z or radius, a word that is not a number, a
/// "comment particle_radius" that is not one number or is given twice),
/// Truncated (the body ends before its last vertex), EmptyMesh (no vertices), NonFinite (a
/// non-finite coordinate, radius or header radius), InvalidArgument (a radius or header radius
/// <= 0).
Result<ParticleFrame> readParticlePly(const std::filesystem::path& path);

} // namespace sluice::bake::detail
