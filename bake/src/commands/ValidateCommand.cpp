// `sluice-bake validate`: an asset against the exact CGAL reference of its mesh, with limits.
#include <cmath>
#include <iostream>
#include <memory>

#include "commands/CliSupport.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/bake/jobs/ValidateJob.h"
#include "sluice/format/AssetIO.h"

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
    std::string sign; ///< empty: the method the asset records
    std::uint64_t samples = ValidateOptions{}.samplePoints;
    std::uint64_t seed = ValidateOptions{}.seed;
    bool write = false;
    bool quiet = false;
};

int runValidate(const ValidateArgs& args) {
    constexpr std::string_view cmd = "validate";
    const std::string signText = args.sign;
    if (!signText.empty())
        if (Result<SignMode> sign = parseSignMode(signText); !sign)
            return reportBadInput(cmd, "--sign " + signText + ": " + sign.error().detail);
    if (args.write && hasExtension(args.asset, ".vdb"))
        return reportBadInput(cmd,
                              "--write needs a collider asset (.slc), not '" + args.asset + "'");

    Result<format::ColliderAsset> asset = loadAsset(args.asset);
    if (!asset)
        return reportFileError(cmd, "cannot read asset", args.asset, asset.error());
    Result<ImportedMesh> mesh = loadMesh(args.mesh, asset->meta.bake.scale);
    if (!mesh)
        return reportFileError(cmd, "cannot read mesh", args.mesh, mesh.error());

    ValidateOptions options;
    options.samplePoints = args.samples;
    options.seed = args.seed;
    // A .vdb grid records no bake, so its sign method is unknown: auto.
    const bool vdb = hasExtension(args.asset, ".vdb");
    const std::string signUsed = !signText.empty() ? signText
                                 : vdb             ? std::string("auto")
                                                   : defaultValidateSign(asset->meta);
    options.sign = parseSignMode(signUsed).value();

    const std::uint64_t gridPoints = asset->pointCount();
    const std::uint64_t toCheck = gridPoints > options.maxFullPoints
                                      ? std::min(gridPoints, options.samplePoints)
                                      : gridPoints;
    Result<ValidationReport> report = [&] {
        Progress progress("validating", toCheck, !args.quiet && !args.json);
        return validate(*asset, *mesh, options, &progress);
    }();
    if (!report)
        return reportError(cmd, "cannot validate '" + args.asset + "' against '" + args.mesh + "'",
                           report.error());

    const format::ValidationFigures& f = report->figures;
    const double maxError = args.maxErrorGiven ? args.maxError : defaultMaxError(*asset);
    const bool errorOk = f.maxError <= maxError;
    const bool signOk = report->signMismatchPercent <= args.maxSignErrors;
    const bool hashKnown = !asset->meta.sourceHash.empty();
    const bool hashMatches = asset->meta.sourceHash == mesh->sourceHash;

    bool written = false;
    if (args.write) {
        asset->meta.validation = f;
        if (Result<void> ok = format::writeAsset(args.asset, *asset); !ok)
            return reportFileError(cmd, "cannot update", args.asset, ok.error());
        written = true;
    }

    if (args.json) {
        const ValidateRequest request{.maxSignErrorsPercent = args.maxSignErrors};
        const ValidateOutcome outcome{*report, maxError, errorOk && signOk};
        std::cout << validateReportJson(outcome, *asset, *mesh, args.asset, args.mesh, request,
                                        written)
                  << '\n';
    } else {
        auto verdict = [](bool ok) { return ok ? "ok" : "OVER"; };
        std::cout << "validate " << args.asset << " against " << args.mesh << '\n'
                  << "  reference  CGAL, " << signMethodName(report->referenceSign) << " sign, ";
        if (asset->sparse())
            std::cout << "sparse: " << report->bandPoints << " band voxels (error, sign) and "
                      << report->tilePoints << " other grid points (sign)\n";
        else
            std::cout << (report->sampled ? "stratified sample of " : "every grid point: ")
                      << f.pointsChecked << " of " << gridPoints << " points\n";
        std::cout << "  distance   max " << num(f.maxError, 3) << "  mean " << num(f.meanError, 3)
                  << "  rms " << num(f.rmsError, 3) << " voxels   limit " << num(maxError, 3)
                  << "  " << verdict(errorOk) << '\n'
                  << "  sign       " << plural(f.signMismatches, "mismatch", "mismatches") << " of "
                  << report->signComparedPoints << " compared points ("
                  << num(report->signMismatchPercent, 3) << " %)   limit "
                  << num(args.maxSignErrors, 3) << " %  " << verdict(signOk) << '\n'
                  << "  eikonal    |grad phi| median " << num(f.eikonalMedian, 4) << "  p99 "
                  << num(f.eikonalP99, 4) << "  outside [0.5, 1.5] "
                  << num(100.0 * f.eikonalOutsideShare, 3) << " %\n";
        if (hashKnown && !hashMatches)
            std::cout << "  note       the mesh file's hash differs from the asset's source ("
                      << asset->meta.sourceFile << ")\n";
        if (written)
            std::cout << "  wrote the figures into " << args.asset << '\n';
        std::cout << "  result     " << (errorOk && signOk ? "PASS" : "FAIL") << '\n';
    }
    return errorOk && signOk ? kExitOk : kExitCheckFailed;
}

} // namespace

Command addValidateCommand(CLI::App& parent) {
    auto args = std::make_shared<ValidateArgs>();
    CLI::App* app = parent.add_subcommand(
        "validate", "Check an asset against the exact CGAL reference of MESH (imported at the "
                    "scale the asset records). Exit 0 within the limits, 1 over them.");
    app->add_option("ASSET", args->asset, "collider asset (.slc, or a .vdb grid)")->required();
    app->add_option("MESH", args->mesh, "the mesh the asset was baked from")->required();
    app->add_flag("--json", args->json, "print the report as JSON");
    app->add_option_function<double>(
           "--max-error", [args](double e) { args->maxError = e, args->maxErrorGiven = true; },
           "[voxels] largest allowed |phi - phi_ref|; default 1e-3, plus the recorded "
           "quantization error for f16 assets")
        ->check(finiteNumber(true));
    app->add_option("--max-sign-errors", args->maxSignErrors,
                    "[%] largest allowed share of sign mismatches (points within 1e-4 voxel of "
                    "the surface are not counted)")
        ->check(numberIn(0.0, 100.0))
        ->capture_default_str();
    app->add_option("--sign", args->sign,
                    "reference sign method: auto, parity, winding (default: what the asset "
                    "records)");
    app->add_option("--samples", args->samples,
                    "sample size for grids over 2M points (stratified: half within 2 voxels of "
                    "the surface)")
        ->check(wholeNumber(1, std::int64_t(1) << 28))
        ->capture_default_str();
    app->add_option("--seed", args->seed, "sampling seed (same seed, same report)")
        ->capture_default_str();
    app->add_flag("--write", args->write,
                  "store the figures in the asset's metadata (rewritten atomically)");
    app->add_flag("-q,--quiet", args->quiet, "no progress bar");
    return {app, [args] { return runValidate(*args); }};
}

} // namespace sluice::bake::cli
