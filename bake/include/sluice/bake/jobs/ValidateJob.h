// One validation as a library call: `sluice-bake validate` defaults, limits and JSON report.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "sluice/bake/import/MeshImport.h"
#include "sluice/bake/jobs/Progress.h"
#include "sluice/bake/validate/Validate.h"
#include "sluice/bake/validate/VolumeMapCheck.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// [voxels] validate's default --max-error beyond quantization. A CGAL bake stores the same
/// reference in fp32, so its error is float rounding (~1e-7 relative, far below this); anything
/// near a thousandth of a voxel is a real disagreement.
inline constexpr double kDefaultMaxErrorVoxels = 1e-3;

/// Validate's default --max-map-error [share of the kernel's weight]: what a baked volume map may
/// differ from the brute-force integration (VolumeMapCheck.h) by at its worst point.
inline constexpr double kDefaultMaxMapError = 0.05;

/// The options of `sluice-bake validate`, as it spells them.
struct ValidateRequest {
    std::string sign; ///< empty: what the asset records (auto for .vdb)
    std::uint64_t samples = ValidateOptions{}.samplePoints; ///< sample size for large grids
    std::uint64_t seed = ValidateOptions{}.seed;            ///< sampling seed
    std::optional<double> maxError;    ///< [voxels]; empty: defaultMaxError(asset)
    double maxSignErrorsPercent = 0.0; ///< [%]
    double maxMapError = kDefaultMaxMapError; ///< volume maps: largest |baked - brute force|
    bool levelSetSource = false;       ///< the asset came from a .vdb grid
};

/// A validation with its verdict.
struct ValidateOutcome {
    ValidationReport report;
    double maxError = 0.0; ///< [voxels] the limit applied
    std::vector<VolumeMapCheck> volumeMaps; ///< each baked volume map against brute force
    bool withinLimits = false;              ///< the field's figures and every volume map's
};

/// [voxels] validate's default --max-error: 1e-3 plus, for fp16, the recorded quantization
/// error (or the fp16 rounding bound 2^-11 max |phi| if none is recorded).
double defaultMaxError(const format::ColliderAsset& asset);

/// Validate's default --sign: the method the asset was baked with ("auto" for level sets).
std::string defaultValidateSign(const format::ColliderMeta& meta);

/// Grid points validate will check (every point, or the sample size on large grids).
std::uint64_t validatePointCount(const format::ColliderAsset& asset,
                                 const ValidateRequest& request);

/// Validates `asset` against `mesh` (imported at the asset's scale). Errors: InvalidArgument
/// ("--sign x: ...") and those of validate().
Result<ValidateOutcome> validateAsset(const format::ColliderAsset& asset, const ImportedMesh& mesh,
                                      const ValidateRequest& request, Progress* progress = nullptr);

/// The report as `sluice-bake validate --json` prints it (2-space indent); `assetName` and
/// `meshName` are the paths it names, `written` whether --write stored the figures.
std::string validateReportJson(const ValidateOutcome& outcome, const format::ColliderAsset& asset,
                               const ImportedMesh& mesh, const std::string& assetName,
                               const std::string& meshName, const ValidateRequest& request,
                               bool written);

} // namespace sluice::bake
