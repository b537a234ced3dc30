// Particle frames (PLY) to OpenVDB narrow-band level sets: what `sluice-bake surface` does.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// How particles become a level set. By default the level set is the surface of the fluid the
/// particles sample: every particle of radius r becomes a sphere of radius 2 r (one lattice
/// spacing, since sluice-play's r is half its spacing; that closes the gaps between lattice
/// neighbours), and the union of those spheres is then eroded by r
/// (openvdb::tools::LevelSetFilter::offset, re-normalised as it goes), so that a block of
/// particles on a lattice of spacing s ends s / 2 beyond its outermost particle centres, with no
/// pockets inside. With per-vertex radii each sphere has radius 2 r_i and the union is eroded
/// by the frame's smallest r_i. With `spheres`, the level set is the plain union of the
/// particles' spheres of radius r (openvdb::tools::ParticlesToLevelSet). OpenVDB rasterises
/// spheres of 1.5 to 100 voxels (radius 2 r, or r with `spheres`).
struct SurfaceOptions {
    /// [world units] every particle's radius; 0: each file's per-vertex "radius" property, or
    /// else the radius its header records ("comment particle_radius R", as sluice-play writes).
    double radius = 0.0;
    /// [world units] 0: half the radius of the first frame (with per-vertex radii, half its
    /// smallest radius), so a particle's radius spans 2 voxels.
    double voxelSize = 0.0;
    /// [voxels] half-width of the narrow band (OpenVDB's default, 3).
    double halfWidth = 3.0;
    /// The plain union of the particles' spheres instead of the fluid's surface.
    bool spheres = false;
};

/// Where a frame's particle radius came from, in order of precedence.
enum class RadiusSource {
    Option,    ///< SurfaceOptions::radius (--radius)
    PerVertex, ///< the file's per-vertex "radius" property
    Header,    ///< the file's "comment particle_radius R" header line
};

/// One frame's grid, as written.
struct SurfaceFrame {
    std::string name;                   ///< the grid's name: the file's stem ("frame_000015")
    std::uint64_t particles = 0;        ///< read from the file
    std::uint64_t ignoredParticles = 0; ///< per-vertex radii OpenVDB skips (sphere outside 1.5
                                        ///< to 100 voxels)
    std::uint64_t activeVoxels = 0;     ///< of the narrow band
    RadiusSource radiusSource = RadiusSource::Option;
    double radius = 0.0; ///< [world units] every particle's radius; 0 when read per vertex
};

/// What writeParticleSurfaces did.
struct SurfaceReport {
    double voxelSize = 0.0;           ///< [world units] the voxel size used
    double radius = 0.0;              ///< [world units] SurfaceOptions::radius (0: from the files)
    std::vector<SurfaceFrame> frames; ///< in the order written
};

/// The particle files `input` names: `input` itself if it is a file; if it is a folder, every
/// regular file in it ending in ".ply" (any case), sorted by name (other files, such as
/// sluice-play's "frame_NNNNNN.bodies.json", are ignored). Errors: Io (missing, neither a file
/// nor a folder, unreadable folder), EmptyMesh (a folder without .ply files). Every message
/// names `input`.
Result<std::vector<std::filesystem::path>> listParticleFrames(const std::filesystem::path& input);

/// Reads each PLY frame (ASCII or binary; the "vertex" element's x, y, z and optional radius,
/// and the header's optional "comment particle_radius R"), turns its particles into a FloatGrid
/// of class level set as SurfaceOptions says (voxel size and radius from `options`; the voxel
/// size fixed by the first frame when not given; the radius, by precedence, from
/// `options.radius`, the per-vertex radii, the header), named after the file's stem, with the
/// source file, its hash, the radius and the kind of surface in grid metadata
/// ("sluice_source_file", "sluice_source_hash", "sluice_particle_radius" (0 when per vertex),
/// "sluice_surface": "fluid" or "spheres"), and writes all grids into the one .vdb file
/// `output`, atomically (temporary file beside it, then rename). All grids are held in memory
/// until the write. On any error nothing is written and `output` is left as it was. Errors,
/// each naming the file: those of reading a PLY (Io, BadMagic, MeshImport, Truncated,
/// EmptyMesh, NonFinite, InvalidArgument for a radius <= 0, per vertex or in the header), and
/// InvalidArgument (no radius given nor in the file; radius or voxel size not finite and > 0;
/// a sphere radius outside 1.5 to 100 voxels; every per-vertex one outside them), SizeOverflow
/// (coordinates beyond OpenVDB's index range at this voxel size, or out of memory), Io (the
/// write).
Result<SurfaceReport> writeParticleSurfaces(const std::vector<std::filesystem::path>& frames,
                                            const std::filesystem::path& output,
                                            const SurfaceOptions& options);

} // namespace sluice::bake
