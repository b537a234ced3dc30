// Particle frames (PLY) to OpenVDB narrow-band level sets: what `sluice-bake surface` does.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// How particles become a level set. Every particle is a sphere; the level set is their union
/// (openvdb::tools::ParticlesToLevelSet), which rasterises spheres of 1.5 to 100 voxels.
struct SurfaceOptions {
    /// [world units] every particle's radius; 0: each file's per-vertex "radius" property.
    double radius = 0.0;
    /// [world units] 0: half the radius (with per-vertex radii, half the smallest radius of the
    /// first frame), so a particle spans 4 voxels.
    double voxelSize = 0.0;
    /// [voxels] half-width of the narrow band (OpenVDB's default, 3).
    double halfWidth = 3.0;
};

/// One frame's grid, as written.
struct SurfaceFrame {
    std::string name;                   ///< the grid's name: the file's stem ("frame_000015")
    std::uint64_t particles = 0;        ///< read from the file
    std::uint64_t ignoredParticles = 0; ///< per-vertex radii OpenVDB skips (< 1.5 or > 100 voxels)
    std::uint64_t activeVoxels = 0;     ///< of the narrow band
};

/// What writeParticleSurfaces did.
struct SurfaceReport {
    double voxelSize = 0.0;           ///< [world units] the voxel size used
    double radius = 0.0;              ///< [world units] the radius used; 0 when read per vertex
    std::vector<SurfaceFrame> frames; ///< in the order written
};

/// The particle files `input` names: `input` itself if it is a file; if it is a folder, every
/// regular file in it ending in ".ply" (any case), sorted by name (other files, such as
/// sluice-play's "frame_NNNNNN.bodies.json", are ignored). Errors: Io (missing, neither a file
/// nor a folder, unreadable folder), EmptyMesh (a folder without .ply files). Every message
/// names `input`.
Result<std::vector<std::filesystem::path>> listParticleFrames(const std::filesystem::path& input);

/// Reads each PLY frame (ASCII or binary; the "vertex" element's x, y, z and optional radius),
/// rasterises its particles into a FloatGrid of class level set (voxel size and radius from
/// `options`; the voxel size fixed by the first frame when not given), named after the file's
/// stem, with the source file, its hash and the radius in grid metadata ("sluice_source_file",
/// "sluice_source_hash", "sluice_particle_radius" (0 when per vertex)), and writes all grids
/// into the one .vdb file `output`, atomically (temporary file beside it, then rename). All
/// grids are held in memory until the write. On any error nothing is written and `output` is
/// left as it was. Errors, each naming the file: those of reading a PLY (Io, BadMagic,
/// MeshImport, Truncated, EmptyMesh, NonFinite, InvalidArgument for a radius <= 0), and
/// InvalidArgument (no radius given nor in the file; radius or voxel size not finite and > 0;
/// a radius outside 1.5 to 100 voxels; every per-vertex radius outside them), SizeOverflow
/// (coordinates beyond OpenVDB's index range at this voxel size, or out of memory), Io (the
/// write).
Result<SurfaceReport> writeParticleSurfaces(const std::vector<std::filesystem::path>& frames,
                                            const std::filesystem::path& output,
                                            const SurfaceOptions& options);

} // namespace sluice::bake
