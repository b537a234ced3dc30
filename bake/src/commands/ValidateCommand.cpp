// `sluice-bake validate`: an asset against the exact CGAL reference of its mesh, with limits.
#include <iostream>

#include "commands/CliSupport.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/bake/jobs/ValidateJob.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::bake::cli {
namespace {

/// [%] default --max-sign-errors: a CGAL bake has the reference's signs everywhere outside the
/// 1e-4-voxel surface band, so any mismatch is a failure.
constexpr double kDefaultMaxSignErrorsPercent = 0.0;

struct ValidateArgs {
    std::string asset;
    std::string mesh;
    bool json = false;
    double maxError = kDefaultMaxErrorVoxels;
    bool maxErrorGiven = false;
    double maxSignErrors = kDefaultMaxSignErrorsPercent;
    double maxMapError = kDefaultMaxMapError;
    std::string sign; ///< empty: the method the asset records
    std::uint64_t samples = ValidateOptions{}.samplePoints;
    std::uint64_t seed = ValidateOptions{}.seed;
    bool write = false;
    bool quiet = false;
};

/// The request the arguments make (validateAsset's).
ValidateRequest requestFor(const ValidateArgs& args) {
    ValidateRequest request;
    request.sign = args.sign;
    request.samples = args.samples;
    request.seed = args.seed;
    if (args.maxErrorGiven)
        request.maxError = args.maxError;
    request.maxSignErrorsPercent = args.maxSignErrors;
    request.maxMapError = args.maxMapError;
    // A .vdb grid records no bake, so its sign method is unknown: auto.
    request.levelSetSource = hasExtension(args.asset, ".vdb");
    return request;
}

/// The report for people: the reference, what was compared, each figure against its limit.
void printReport(const ValidateArgs& args, const format::ColliderAsset& asset,
                 const ImportedMesh& mesh, const ValidateOutcome& outcome, bool written) {
    const ValidationReport& report = outcome.report;
    const format::ValidationFigures& f = report.figures;
    const bool errorOk = f.maxError <= outcome.maxError;
    const bool signOk = report.signMismatchPercent <= args.maxSignErrors;
    auto verdict = [](bool ok) { return ok ? "ok" : "OVER"; };
    std::cout << "validate " << args.asset << " against " << args.mesh << '\n'
              << "  reference  CGAL, " << signMethodName(report.referenceSign) << " sign, ";
    if (asset.sparse())
        std::cout << "sparse: " << report.bandPoints << " band voxels (error, sign) and "
                  << report.tilePoints << " other grid points (sign)\n";
    else
        std::cout << (report.sampled ? "stratified sample of " : "every grid point: ")
                  << f.pointsChecked << " of " << asset.pointCount() << " points\n";
    std::cout << "  distance   max " << num(f.maxError, 3) << "  mean " << num(f.meanError, 3)
              << "  rms " << num(f.rmsError, 3) << " voxels   limit " << num(outcome.maxError, 3)
              << "  " << verdict(errorOk) << '\n'
              << "  sign       " << plural(f.signMismatches, "mismatch", "mismatches") << " of "
              << report.signComparedPoints << " compared points ("
              << num(report.signMismatchPercent, 3) << " %)   limit " << num(args.maxSignErrors, 3)
              << " %  " << verdict(signOk) << '\n'
              << "  eikonal    |grad phi| median " << num(f.eikonalMedian, 4) << "  p99 "
              << num(f.eikonalP99, 4) << "  outside [0.5, 1.5] "
              << num(100.0 * f.eikonalOutsideShare, 3) << " %\n";
    for (const VolumeMapCheck& c : outcome.volumeMaps)
        std::cout << "  volume map support " << num(c.support) << ": " << c.pointsChecked
                  << " points against brute force (" << kVolumeMapCheckSteps
                  << " cells per support), max " << num(c.maxError, 3) << "  mean "
                  << num(c.meanError, 3) << "   limit " << num(args.maxMapError, 3) << "  "
                  << verdict(c.maxError <= args.maxMapError) << "; " << c.nonZeroBeyondReach
                  << " of the " << c.zeroPoints << " points beyond its reach not 0  "
                  << verdict(c.nonZeroBeyondReach == 0) << '\n';
    if (!asset.meta.sourceHash.empty() && asset.meta.sourceHash != mesh.sourceHash)
        std::cout << "  note       the mesh file's hash differs from the asset's source ("
                  << asset.meta.sourceFile << ")\n";
    if (written)
        std::cout << "  wrote the figures into " << args.asset << '\n';
    std::cout << "  result     " << (outcome.withinLimits ? "PASS" : "FAIL") << '\n';
}

int runValidate(const ValidateArgs& args) {
    constexpr std::string_view cmd = "validate";
    if (!args.sign.empty())
        if (Result<SignMode> sign = parseSignMode(args.sign); !sign)
            return reportBadInput(cmd, "--sign " + args.sign + ": " + sign.error().detail);
    if (args.write && hasExtension(args.asset, ".vdb"))
        return reportBadInput(cmd,
                              "--write needs a collider asset (.slc), not '" + args.asset + "'");

    Result<format::ColliderAsset> asset = loadAsset(args.asset);
    if (!asset)
        return reportFileError(cmd, "cannot read asset", args.asset, asset.error());
    Result<ImportedMesh> mesh = loadMesh(args.mesh, asset->meta.bake.scale);
    if (!mesh)
        return reportFileError(cmd, "cannot read mesh", args.mesh, mesh.error());

    const ValidateRequest request = requestFor(args);
    Result<ValidateOutcome> outcome = [&] {
        Progress progress("validating", validatePointCount(*asset, request),
                          !args.quiet && !args.json);
        return validateAsset(*asset, *mesh, request, &progress);
    }();
    if (!outcome)
        return reportError(cmd, "cannot validate '" + args.asset + "' against '" + args.mesh + "'",
                           outcome.error());

    bool written = false;
    if (args.write) {
        asset->meta.validation = outcome->report.figures;
        if (Result<void> ok = format::writeAsset(args.asset, *asset); !ok)
            return reportFileError(cmd, "cannot update", args.asset, ok.error());
        written = true;
    }
    if (args.json)
        std::cout << validateReportJson(*outcome, *asset, *mesh, args.asset, args.mesh, request,
                                        written)
                  << '\n';
    else
        printReport(args, *asset, *mesh, *outcome, written);
    return outcome->withinLimits ? kExitOk : kExitCheckFailed;
}

/// The options of `validate`, bound to `args`.
void addValidateOptions(CLI::App& app, ValidateArgs& args) {
    app.add_option("ASSET", args.asset, "collider asset (.slc, or a .vdb grid)")->required();
    app.add_option("MESH", args.mesh, "the mesh the asset was baked from")->required();
    app.add_flag("--json", args.json, "print the report as JSON");
    app.add_option_function<double>(
           "--max-error", [&args](double e) { args.maxError = e, args.maxErrorGiven = true; },
           "[voxels] largest allowed |phi - phi_ref|; default 1e-3, plus the recorded "
           "quantization error for f16 assets")
        ->check(finiteNumber(true));
    app.add_option("--max-map-error", args.maxMapError,
                   "largest allowed |baked - brute force| of a volume map baked into the asset "
                   "[share of the kernel's weight]")
        ->check(finiteNumber(true))
        ->capture_default_str();
    app.add_option("--max-sign-errors", args.maxSignErrors,
                   "[%] largest allowed share of sign mismatches (points within 1e-4 voxel of "
                   "the surface are not counted)")
        ->check(numberIn(0.0, 100.0))
        ->capture_default_str();
    app.add_option("--sign", args.sign,
                   "reference sign method: auto, parity, winding (default: what the asset "
                   "records)");
    app.add_option("--samples", args.samples,
                   "sample size for grids over 2M points (stratified: half within 2 voxels of "
                   "the surface)")
        ->check(wholeNumber(1, std::int64_t(1) << 28))
        ->capture_default_str();
    app.add_option("--seed", args.seed, "sampling seed (same seed, same report)")
        ->capture_default_str();
    app.add_flag("--write", args.write,
                 "store the figures in the asset's metadata (rewritten atomically)");
    app.add_flag("-q,--quiet", args.quiet, "no progress bar");
}

} // namespace

Command addValidateCommand(CLI::App& parent) {
    return addSubcommand(parent, "validate",
                         "Check an asset against the exact CGAL reference of MESH (imported at the "
                         "scale the asset records). Exit 0 within the limits, 1 over them.",
                         addValidateOptions, runValidate);
}

} // namespace sluice::bake::cli
