// One validation as a library call: what `sluice-bake validate` does between parsing and printing.
#include "sluice/bake/jobs/ValidateJob.h"

#include <algorithm>
#include <cmath>

#include "commands/CliSupport.h"

namespace sluice::bake {

double defaultMaxError(const format::ColliderAsset& asset) {
    if (asset.meta.storage != format::Storage::F16)
        return kDefaultMaxErrorVoxels;
    double quantization = asset.meta.quantizationError;
    if (quantization <= 0.0) {
        double largest = 0.0;
        for (float phi : asset.distances)
            largest = std::max(largest, double(std::abs(phi)));
        quantization = largest * 0x1.0p-11;
    }
    return kDefaultMaxErrorVoxels + quantization / asset.meta.voxelSize;
}

std::string defaultValidateSign(const format::ColliderMeta& meta) {
    switch (meta.bake.signUsed) {
    case format::SignMethod::Parity:
        return "parity";
    case format::SignMethod::Winding:
        return "winding";
    case format::SignMethod::Level:
        return "auto";
    }
    return "auto";
}

std::uint64_t validatePointCount(const format::ColliderAsset& asset,
                                 const ValidateRequest& request) {
    const std::uint64_t gridPoints = asset.pointCount();
    return gridPoints > ValidateOptions{}.maxFullPoints ? std::min(gridPoints, request.samples)
                                                        : gridPoints;
}

Result<ValidateOutcome> validateAsset(const format::ColliderAsset& asset, const ImportedMesh& mesh,
                                      const ValidateRequest& request, Progress* progress) {
    const std::string signText = !request.sign.empty()    ? request.sign
                                 : request.levelSetSource ? std::string("auto")
                                                          : defaultValidateSign(asset.meta);
    Result<SignMode> sign = parseSignMode(signText);
    if (!sign)
        return fail(ErrorCode::InvalidArgument, "--sign " + signText + ": " + sign.error().detail);
    if (request.samples < 1 || request.samples > (std::uint64_t(1) << 28))
        return fail(ErrorCode::InvalidArgument,
                    "--samples " + std::to_string(request.samples) + ": not in range [1 - 2^28]");
    ValidateOptions options;
    options.samplePoints = request.samples;
    options.seed = request.seed;
    options.sign = *sign;
    Result<ValidationReport> report = validate(asset, mesh, options, progress);
    if (!report)
        return report.error();
    ValidateOutcome outcome;
    outcome.report = std::move(*report);
    outcome.maxError = request.maxError ? *request.maxError : defaultMaxError(asset);
    outcome.volumeMaps = checkVolumeMaps(asset);
    outcome.withinLimits =
        outcome.report.figures.maxError <= outcome.maxError &&
        outcome.report.signMismatchPercent <= request.maxSignErrorsPercent &&
        std::all_of(outcome.volumeMaps.begin(), outcome.volumeMaps.end(),
                    [&](const VolumeMapCheck& c) {
                        return c.maxError <= request.maxMapError && c.nonZeroBeyondReach == 0;
                    });
    return outcome;
}

namespace {
nlohmann::ordered_json volumeMapChecksJson(const std::vector<VolumeMapCheck>& checks) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const VolumeMapCheck& c : checks)
        out.push_back({{"support", c.support},
                       {"pointsChecked", c.pointsChecked},
                       {"maxError", c.maxError},
                       {"meanError", c.meanError},
                       {"worstPoint", c.worstPoint},
                       {"zeroPoints", c.zeroPoints},
                       {"nonZeroBeyondReach", c.nonZeroBeyondReach}});
    return out;
}
} // namespace

std::string validateReportJson(const ValidateOutcome& outcome, const format::ColliderAsset& asset,
                               const ImportedMesh& mesh, const std::string& assetName,
                               const std::string& meshName, const ValidateRequest& request,
                               bool written) {
    const ValidationReport& report = outcome.report;
    const bool hashKnown = !asset.meta.sourceHash.empty();
    const bool hashMatches = asset.meta.sourceHash == mesh.sourceHash;
    nlohmann::ordered_json out = {{"asset", assetName},
                                  {"mesh", meshName},
                                  {"sampled", report.sampled},
                                  {"referenceSign", format::signMethodName(report.referenceSign)},
                                  {"signComparedPoints", report.signComparedPoints},
                                  {"signMismatchPercent", report.signMismatchPercent},
                                  {"bandPoints", report.bandPoints},
                                  {"tilePoints", report.tilePoints},
                                  {"figures", cli::toJson(report.figures)},
                                  {"volumeMaps", volumeMapChecksJson(outcome.volumeMaps)},
                                  {"limits",
                                   {{"maxError", outcome.maxError},
                                    {"maxSignErrorsPercent", request.maxSignErrorsPercent},
                                    {"maxMapError", request.maxMapError}}},
                                  {"withinLimits", outcome.withinLimits},
                                  {"sourceHashMatches", hashKnown
                                                            ? nlohmann::ordered_json(hashMatches)
                                                            : nlohmann::ordered_json()},
                                  {"written", written}};
    return out.dump(2);
}

} // namespace sluice::bake
