// Particle files in the PLY format that Blender, Houdini and MeshLab read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "sluice/format/support/Result.h"
#include "sluice/rt/sim/SceneSetup.h"

namespace sluice::rt {

/// The bytes of a binary little-endian PLY file with one vertex per particle, properties
/// `float x y z vx vy vz` [m, m/s] and `uint id`, sorted by id so the file does not depend on
/// the solver's memory order. With `particleRadius` > 0 the header says it in a comment line,
/// `comment particle_radius R` [m], which `sluice-bake surface` reads.
std::vector<std::byte> encodePly(std::span<const ParticleState> particles,
                                 float particleRadius = 0.0f);

/// Writes encodePly's bytes atomically (temporary file, then rename).
Result<void> writePly(const std::filesystem::path& path, std::span<const ParticleState> particles,
                      float particleRadius = 0.0f);

} // namespace sluice::rt
