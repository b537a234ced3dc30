// `sluice-bake export`: a collider asset out as an OpenVDB float level set or a NanoVDB grid.
#include <iostream>

#include "commands/CliSupport.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/bake/interop/NanoVdbIO.h"
#include "sluice/bake/interop/VdbIO.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::bake::cli {
namespace {

struct ExportArgs {
    std::string asset;
    std::string output;
    bool quiet = false;
};

int runExport(const ExportArgs& args) {
    constexpr std::string_view cmd = "export";
    const bool nvdb = hasExtension(args.output, ".nvdb");
    if (!hasExtension(args.output, ".vdb") && !nvdb)
        return reportBadInput(cmd,
                              "'" + args.output + "': the output must be a .vdb or .nvdb file");
    if (hasExtension(args.asset, ".vdb"))
        return reportBadInput(cmd, "'" + args.asset +
                                       "' is already a .vdb file (export converts a collider "
                                       "asset, .slc, to OpenVDB)");
    if (Result<void> out = prepareOutputPath(args.output); !out)
        return reportFileError(cmd, "cannot write", args.output, out.error());
    Result<format::ColliderAsset> asset = format::readAsset(args.asset);
    if (!asset)
        return reportFileError(cmd, "cannot read asset", args.asset, asset.error());
    if (Result<void> ok = nvdb ? exportNvdb(*asset, args.output) : exportVdb(*asset, args.output);
        !ok)
        return reportFileError(cmd, "cannot write", args.output, ok.error());
    if (!args.quiet)
        std::cout << "exported " << args.asset << " -> " << args.output << " ("
                  << (asset->sparse() ? "sparse " : "") << "level set, "
                  << describeDims(asset->meta.dims) << ", voxel " << num(asset->meta.voxelSize)
                  << " world units)\n";
    return kExitOk;
}

/// The options of `export`, bound to `args`.
void addExportOptions(CLI::App& app, ExportArgs& args) {
    app.add_option("ASSET", args.asset, "collider asset (.slc)")->required();
    app.add_option("OUT", args.output, "output file (.vdb or .nvdb)")->required();
    app.add_flag("-q,--quiet", args.quiet, "no summary");
}

} // namespace

Command addExportCommand(CLI::App& parent) {
    return addSubcommand(
        parent, "export",
        "Write an asset as an OpenVDB float level set (.vdb; every grid point an "
        "active voxel, or the band of a sparse asset) or a sparse asset's NanoVDB grid "
        "(.nvdb), atomically.",
        addExportOptions, runExport);
}

} // namespace sluice::bake::cli
