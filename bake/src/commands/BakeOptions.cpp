// The options of `bake`, bound to BakeArgs.
#include "commands/CliSupport.h"

namespace sluice::bake::cli {

/// The options of `bake`, bound to `args`.
void addBakeOptions(CLI::App& app, BakeArgs& args) {
    app.add_option("MESH", args.mesh, "input mesh file")->required();
    app.add_option("-o,--output", args.output, "output asset file (.slc)")
        ->required()
        ->type_name("OUT");
    app.add_option("--backend", args.backend,
                   "where distances are computed: auto (gpu where an OpenGL 4.5 context opens, "
                   "otherwise cgal), gpu (OpenGL 4.5 compute, headless; exit 3 without a "
                   "context) or cgal (the exact CPU reference, all cores). All give the same "
                   "exact field")
        ->capture_default_str();
    CLI::Option* resolution =
        app.add_option("--resolution", args.resolution,
                       "[voxels] along the longest side of the mesh box, 1..4096")
            ->check(wholeNumber(1, 4096))
            ->capture_default_str();
    CLI::Option* voxelSize = app.add_option("--voxel-size", args.voxelSize,
                                            "[world units] grid spacing, instead of --resolution")
                                 ->check(finiteNumber(false));
    resolution->excludes(voxelSize);
    voxelSize->excludes(resolution);
    app.add_option("--padding", args.padding, "[voxels] margin on every side of the mesh box")
        ->check(finiteNumber(true))
        ->capture_default_str();
    app.add_option("--sign", args.sign,
                   "inside/outside method: auto (parity if closed and not self-intersecting, "
                   "else winding), parity, winding. On the GPU, parity is the winding number of "
                   "the consistently oriented closed mesh rounded, odd meaning inside (equal to "
                   "ray parity on a closed surface)")
        ->capture_default_str();
    app.add_option("--scale", args.scale, "uniform scale applied to the mesh at import")
        ->check(finiteNumber(false))
        ->capture_default_str();
    app.add_option("--storage", args.storage, "sample type in the file: f32 or f16")
        ->capture_default_str();
    CLI::Option* sparse =
        app.add_flag("--sparse", args.sparse,
                     "write a sparse collider: a NanoVDB narrow band of exact distances with "
                     "signed tiles elsewhere; no dense point limit (resolution up to 4096)");
    app.add_option("--band", args.band,
                   "[voxels] --sparse: half-width of the band of exact distances, 1..64")
        ->needs(sparse)
        ->check(finiteNumber(false))
        ->capture_default_str();
    CLI::Option* forSpacing =
        app.add_option("--for-spacing", args.forSpacing,
                       "[world units] --sparse: pick the band a scene of this particle spacing "
                       "needs, for a static collider or a dynamic body placed at scale 1, "
                       "instead of --band")
            ->needs(sparse)
            ->excludes("--band")
            ->check(finiteNumber(false));
    app.add_option("--for-kernel-radius", args.forKernelRadius,
                   "[world units] --for-spacing: the scene's kernel radius, when it sets one "
                   "(default 2 x spacing)")
        ->needs(forSpacing)
        ->check(finiteNumber(false));
    app.add_option("--volume-map", args.volumeMaps,
                   "[world units] bake the boundary model's volume map for this kernel radius "
                   "over the collider's placement scale (a scene of h = 0.04 placing it at "
                   "scale 2: 0.02), so the scene loads without building it; repeat or list "
                   "with commas, at most 8 (computed on the GPU: needs OpenGL 4.5)")
        ->delimiter(',')
        ->allow_extra_args(false)
        ->check(finiteNumber(false));
    app.add_flag("-q,--quiet", args.quiet, "no progress bar and no summary");
    app.add_flag("--json", args.json, "print the summary as JSON");
    app.add_flag("--profile", args.profile,
                 "print the whole process's time phase by phase, from process start to the "
                 "written file (wall and CPU seconds); gpu backend: also the GPU time of the "
                 "passes, from timer queries");
    app.add_flag("!--no-program-cache", args.programCache,
                 "gpu backend: compile every GPU program instead of loading the driver binaries "
                 "cached in $XDG_CACHE_HOME/sluice (or ~/.cache/sluice) by earlier runs; "
                 "SLUICE_PROGRAM_CACHE=0 in the environment does the same");
}

} // namespace sluice::bake::cli
