// Particle frames to OpenVDB level sets: OpenVDB's sphere rasteriser (and, for the fluid's
// surface, an erosion of the union of spheres), one grid per frame.
#include "sluice/bake/interop/ParticleLevelSet.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <new>
#include <string>
#include <system_error>

#include "import/PlyCheck.h"
#include "interop/ParticlePly.h"
#include "interop/VdbHeaders.h"
#include "interop/VdbWrite.h"
#include "sluice/format/support/NumberText.h"

SLUICE_VDB_WARNINGS_OFF
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
SLUICE_VDB_WARNINGS_ON

namespace fs = std::filesystem;

namespace sluice::bake {
namespace {

// ParticlesToLevelSet skips spheres outside these radii [voxels] (its defaults: below 1.5 a
// sphere is under the grid's Nyquist limit; 100 is its "probably too large").
constexpr double kMinRadiusVoxels = 1.5;
constexpr double kMaxRadiusVoxels = 100.0;

constexpr const char* kMetaSourceFile = "sluice_source_file";
constexpr const char* kMetaSourceHash = "sluice_source_hash";
constexpr const char* kMetaRadius = "sluice_particle_radius";
constexpr const char* kMetaSurface = "sluice_surface";

/// The fluid's surface: spheres of twice the particle radius (one lattice spacing), which close
/// the gaps between lattice neighbours, eroded by one particle radius.
constexpr double kFluidSphereScale = 2.0;

std::string quoted(const fs::path& path) {
    return "'" + path.string() + "'";
}

/// Up to 6 significant digits, for messages.

/// The particle-list interface ParticlesToLevelSet reads (its header's "struct ParticleList"),
/// every radius times `scale`.
class ParticleList {
public:
    using PosType = openvdb::Vec3R;

    ParticleList(const detail::ParticleFrame& frame, double scale)
        : m_frame(frame), m_scale(scale) {}

    std::size_t size() const { return m_frame.positions.size(); }
    void getPos(std::size_t n, openvdb::Vec3R& xyz) const {
        const glm::dvec3& p = m_frame.positions[n];
        xyz = openvdb::Vec3R(p.x, p.y, p.z);
    }
    void getPosRad(std::size_t n, openvdb::Vec3R& xyz, openvdb::Real& radius) const {
        getPos(n, xyz);
        radius = m_scale * m_frame.radii[n];
    }

private:
    const detail::ParticleFrame& m_frame;
    double m_scale = 1.0;
};

/// The radius of the spheres rasterised for particles of radius 1.
double sphereScale(const SurfaceOptions& options) {
    return options.spheres ? 1.0 : kFluidSphereScale;
}

/// "the particle radius R is N voxels of S: ..." when the spheres of a uniform radius are outside
/// what OpenVDB rasterises.
Result<void> checkRadiusInVoxels(double radius, double voxelSize, const SurfaceOptions& options) {
    const double scale = sphereScale(options);
    const double voxels = scale * radius / voxelSize;
    if (voxels >= kMinRadiusVoxels && voxels <= kMaxRadiusVoxels)
        return {};
    const std::string spheres =
        options.spheres ? "spheres" : "the fluid's spheres (twice the particle radius)";
    return fail(ErrorCode::InvalidArgument,
                "the particle radius " + format::significant(radius) + " makes spheres of " +
                    format::significant(voxels) + " voxels of --voxel-size " +
                    format::significant(voxelSize) + "; OpenVDB rasterises " + spheres +
                    " of 1.5 to 100 voxels: choose a voxel size from " +
                    format::significant(scale * radius / kMaxRadiusVoxels) + " to " +
                    format::significant(scale * radius / kMinRadiusVoxels));
}

/// Where a frame's radius comes from (--radius, per vertex, the header), or an error saying what
/// to give instead.
Result<RadiusSource> radiusSource(const detail::ParticleFrame& frame, const fs::path& path,
                                  const SurfaceOptions& options) {
    if (options.radius > 0.0)
        return RadiusSource::Option;
    if (!frame.radii.empty())
        return RadiusSource::PerVertex;
    if (frame.headerRadius)
        return RadiusSource::Header;
    return fail(ErrorCode::InvalidArgument,
                quoted(path) + " records no particle size (no per-vertex \"radius\" property, "
                               "no \"comment particle_radius R\" header line) and no --radius "
                               "was given: give --radius R, sluice-play's particle radius being "
                               "half the scene's \"spacing\" (--radius 0.01 for a spacing of "
                               "0.02), or write the frames again with a sluice-play that records "
                               "it");
}

/// Index coordinates are int32: every sphere's band must fit well inside them.
Result<void> checkIndexRange(const detail::ParticleFrame& frame, double reach, double voxelSize,
                             const fs::path& path) {
    double largest = 0.0;
    for (const glm::dvec3& p : frame.positions)
        largest = std::max({largest, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    const double index = (largest + reach) / voxelSize;
    constexpr double kLimit = double(std::numeric_limits<std::int32_t>::max()) / 2;
    if (index < kLimit)
        return {};
    return fail(ErrorCode::SizeOverflow,
                quoted(path) + ": a particle at " + format::significant(largest) +
                    " world units is beyond OpenVDB's index range at voxel size " +
                    format::significant(voxelSize) + "; choose a larger --voxel-size");
}

/// The union of one sphere per particle, radius `scale` times the particle's (`uniform` for
/// every particle when > 0, else per vertex), as a level set; counts what OpenVDB skipped.
openvdb::FloatGrid::Ptr rasteriseSpheres(const detail::ParticleFrame& frame, double uniform,
                                         double scale, double voxelSize, double halfWidth,
                                         SurfaceFrame& summary) {
    openvdb::FloatGrid::Ptr grid =
        openvdb::createLevelSet<openvdb::FloatGrid>(voxelSize, halfWidth);
    openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
    raster.setRmin(kMinRadiusVoxels);
    raster.setRmax(kMaxRadiusVoxels);
    const ParticleList particles(frame, scale);
    if (uniform > 0.0)
        raster.rasterizeSpheres(particles, scale * uniform);
    else
        raster.rasterizeSpheres(particles);
    raster.finalize(/*prune=*/true);
    summary.ignoredParticles = raster.getMinCount() + raster.getMaxCount();
    return grid;
}

/// Moves the zero crossing `distance` [world units] inwards. LevelSetFilter::offset adds to the
/// level set in steps of half a voxel, re-normalising after each, so the band stays a signed
/// distance of the full half-width; a positive offset erodes (ParticleLevelSetTest checks it).
void erode(openvdb::FloatGrid& grid, double distance) {
    openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(grid);
    filter.offset(float(distance));
}

/// One frame's particles as a named level-set grid, with its provenance.
Result<openvdb::FloatGrid::Ptr> rasterise(const detail::ParticleFrame& frame, const fs::path& path,
                                          const SurfaceOptions& options, double voxelSize,
                                          SurfaceFrame& summary) {
    const bool perVertex = summary.radiusSource == RadiusSource::PerVertex;
    const double scale = sphereScale(options);
    const double largestRadius =
        perVertex ? *std::max_element(frame.radii.begin(), frame.radii.end()) : summary.radius;
    const double reach = scale * largestRadius + options.halfWidth * voxelSize;
    if (auto ok = checkIndexRange(frame, reach, voxelSize, path); !ok)
        return ok.error();
    try {
        summary.particles = frame.positions.size();
        openvdb::FloatGrid::Ptr grid =
            rasteriseSpheres(frame, summary.radius, scale, voxelSize, options.halfWidth, summary);
        if (summary.ignoredParticles == summary.particles)
            return fail(
                ErrorCode::InvalidArgument,
                quoted(path) + ": every particle's sphere radius (" +
                    (options.spheres ? "the particle radius" : "twice the particle radius") +
                    ") is outside 1.5 to 100 voxels of " + format::significant(voxelSize) +
                    "; choose another --voxel-size");
        if (!options.spheres)
            erode(*grid, perVertex ? *std::min_element(frame.radii.begin(), frame.radii.end())
                                   : summary.radius);
        summary.activeVoxels = grid->activeVoxelCount();

        grid->setName(summary.name);
        grid->setCreator(std::string("sluice-bake ") + SLUICE_VERSION);
        grid->insertMeta(kMetaSourceFile, openvdb::StringMetadata(path.filename().string()));
        grid->insertMeta(kMetaSourceHash, openvdb::StringMetadata(frame.sourceHash));
        grid->insertMeta(kMetaRadius, openvdb::DoubleMetadata(summary.radius));
        grid->insertMeta(kMetaSurface,
                         openvdb::StringMetadata(options.spheres ? "spheres" : "fluid"));
        return grid;
    } catch (const std::bad_alloc&) {
        return fail(ErrorCode::SizeOverflow, quoted(path) + ": out of memory rasterising " +
                                                 std::to_string(frame.positions.size()) +
                                                 " particles; choose a larger --voxel-size");
    } catch (const std::exception& e) {
        return fail(ErrorCode::InvalidArgument,
                    quoted(path) + ": OpenVDB cannot rasterise the particles: " + e.what());
    }
}

Result<void> checkOptions(const SurfaceOptions& options) {
    if (!std::isfinite(options.radius) || options.radius < 0.0)
        return fail(ErrorCode::InvalidArgument, "--radius must be a finite number > 0");
    if (!std::isfinite(options.voxelSize) || options.voxelSize < 0.0)
        return fail(ErrorCode::InvalidArgument, "--voxel-size must be a finite number > 0");
    if (!std::isfinite(options.halfWidth) || options.halfWidth < 1.0)
        return fail(ErrorCode::InvalidArgument, "the band's half-width must be >= 1 voxel");
    if (options.radius > 0.0 && options.voxelSize > 0.0)
        return checkRadiusInVoxels(options.radius, options.voxelSize, options);
    return {};
}

} // namespace

Result<std::vector<fs::path>> listParticleFrames(const fs::path& input) {
    std::error_code ec;
    const fs::file_status status = fs::status(input, ec);
    if (!fs::exists(status))
        return fail(ErrorCode::Io, "cannot open " + quoted(input) + ": no such file or folder");
    if (fs::is_regular_file(status))
        return std::vector<fs::path>{input};
    if (!fs::is_directory(status))
        return fail(ErrorCode::Io, "cannot open " + quoted(input) + ": not a file or a folder");
    std::vector<fs::path> frames;
    for (fs::directory_iterator it(input, ec), end; !ec && it != end; it.increment(ec))
        if (it->is_regular_file() && detail::lowered(it->path().extension().string()) == ".ply")
            frames.push_back(it->path());
    if (ec)
        return fail(ErrorCode::Io, "cannot list the folder " + quoted(input) + ": " + ec.message());
    if (frames.empty())
        return fail(ErrorCode::EmptyMesh, "the folder " + quoted(input) +
                                              " holds no .ply files (sluice-play --dump-ply "
                                              "writes frame_NNNNNN.ply)");
    std::sort(frames.begin(), frames.end(),
              [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
    return frames;
}

Result<SurfaceReport> writeParticleSurfaces(const std::vector<fs::path>& frames,
                                            const fs::path& output, const SurfaceOptions& options) {
    if (auto ok = checkOptions(options); !ok)
        return ok.error();
    initOpenVdb();
    SurfaceReport report;
    report.radius = options.radius;
    report.voxelSize = options.voxelSize;
    openvdb::GridCPtrVec grids;
    for (const fs::path& path : frames) {
        Result<detail::ParticleFrame> frame = detail::readParticlePly(path);
        if (!frame)
            return frame.error();
        SurfaceFrame summary;
        summary.name = path.stem().string();
        Result<RadiusSource> source = radiusSource(*frame, path, options);
        if (!source)
            return source.error();
        summary.radiusSource = *source;
        summary.radius = *source == RadiusSource::Option   ? options.radius
                         : *source == RadiusSource::Header ? *frame->headerRadius
                                                           : 0.0;
        if (report.voxelSize <= 0.0) {
            // The first frame fixes the voxel size, so every grid of the file shares it.
            const double radius = summary.radius > 0.0
                                      ? summary.radius
                                      : *std::min_element(frame->radii.begin(), frame->radii.end());
            report.voxelSize = radius / 2.0;
        }
        if (summary.radius > 0.0)
            if (auto ok = checkRadiusInVoxels(summary.radius, report.voxelSize, options); !ok)
                return fail(ok.error().code, quoted(path) + ": " + ok.error().detail);
        Result<openvdb::FloatGrid::Ptr> grid =
            rasterise(*frame, path, options, report.voxelSize, summary);
        if (!grid)
            return grid.error();
        grids.push_back(*grid);
        report.frames.push_back(std::move(summary));
    }
    if (auto ok = detail::writeVdbAtomically(grids, output); !ok)
        return ok.error();
    return report;
}

} // namespace sluice::bake
