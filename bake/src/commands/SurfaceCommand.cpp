// `sluice-bake surface`: particle frames (PLY) to OpenVDB level sets, one grid per frame.
#include <iostream>

#include "commands/CliSupport.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/bake/interop/ParticleLevelSet.h"

namespace sluice::bake::cli {
namespace {

struct SurfaceArgs {
    std::string particles;
    std::string output;
    double radius = 0.0;    ///< [world units] 0: each file's per-vertex or header radius
    double voxelSize = 0.0; ///< [world units] 0: half the radius
    bool spheres = false;   ///< the union of the particles' spheres, not the fluid's surface
    bool quiet = false;
};

/// "radius 0.01 (--radius)", "radius per vertex", "radius 0.01 (header)".
std::string radiusOf(const SurfaceFrame& frame) {
    switch (frame.radiusSource) {
    case RadiusSource::Option:
        return "radius " + num(frame.radius) + " (--radius)";
    case RadiusSource::PerVertex:
        return "radius per vertex";
    case RadiusSource::Header:
        return "radius " + num(frame.radius) + " (header)";
    }
    return "";
}

void printSummary(const SurfaceArgs& args, const SurfaceReport& report) {
    std::cout << "surface " << args.particles << " -> " << args.output << " ("
              << plural(report.frames.size(), "level-set grid") << ", "
              << (args.spheres ? "union of particle spheres" : "fluid surface") << ", voxel "
              << num(report.voxelSize) << " world units, band 3 voxels)\n";
    for (const SurfaceFrame& frame : report.frames)
        std::cout << "  " << frame.name << "  " << plural(frame.particles, "particle") << ", "
                  << radiusOf(frame) << ", " << plural(frame.activeVoxels, "active voxel") << '\n';
}

int runSurface(const SurfaceArgs& args) {
    constexpr std::string_view cmd = "surface";
    if (!hasExtension(args.output, ".vdb"))
        return reportBadInput(cmd, "'" + args.output + "': the output must be a .vdb file");
    Result<std::vector<std::filesystem::path>> frames = listParticleFrames(args.particles);
    if (!frames)
        return reportError(cmd, "nothing written", frames.error());
    if (Result<void> out = prepareOutputPath(args.output); !out)
        return reportFileError(cmd, "cannot write", args.output, out.error());

    SurfaceOptions options;
    options.radius = args.radius;
    options.voxelSize = args.voxelSize;
    options.spheres = args.spheres;
    Result<SurfaceReport> report = writeParticleSurfaces(*frames, args.output, options);
    if (!report)
        return reportError(cmd, "nothing written", report.error());
    for (const SurfaceFrame& frame : report->frames)
        if (frame.ignoredParticles > 0)
            std::cerr << "sluice-bake surface: warning: " << frame.name << ": "
                      << frame.ignoredParticles << " of " << frame.particles
                      << " particles have a sphere radius outside 1.5 to 100 voxels and were left "
                         "out\n";
    if (!args.quiet)
        printSummary(args, *report);
    return kExitOk;
}

/// The options of `surface`, bound to `args`.
void addSurfaceOptions(CLI::App& app, SurfaceArgs& args) {
    app.add_option("PARTICLES", args.particles,
                   "a PLY particle file, or a folder whose *.ply files (sorted by name) are the "
                   "frames, as sluice-play --dump-ply writes them")
        ->required();
    app.add_option("-o,--output", args.output,
                   "output .vdb file: one level-set grid per frame, named after its file")
        ->required()
        ->type_name("OUT");
    app.add_option("--radius", args.radius,
                   "[world units] particle radius (sluice-play's is half the scene's spacing); "
                   "default: each file's per-vertex \"radius\" property, else its header's "
                   "\"comment particle_radius R\" (sluice-play writes it)")
        ->check(finiteNumber(false));
    app.add_option("--voxel-size", args.voxelSize,
                   "[world units] default: half the radius of the first frame (the smallest "
                   "per-vertex radius)")
        ->check(finiteNumber(false));
    app.add_flag("--spheres", args.spheres,
                 "the union of one sphere of the particle radius per particle, instead of the "
                 "fluid's surface (spheres of twice the radius, eroded by the radius)");
    app.add_flag("-q,--quiet", args.quiet, "no summary");
}

} // namespace

Command addSurfaceCommand(CLI::App& parent) {
    return addSubcommand(
        parent, "surface",
        "Turn particle frames (PLY) into OpenVDB narrow-band level sets of the fluid's surface "
        "(a lattice block ends half a spacing beyond its outer particles; --spheres: the union "
        "of the particles' spheres): one FloatGrid per frame in one .vdb file, written "
        "atomically.",
        addSurfaceOptions, runSurface);
}

} // namespace sluice::bake::cli
