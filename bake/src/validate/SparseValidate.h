// Private: validate() for sparse assets (band accuracy and tile signs), see SparseValidate.cpp.
#pragma once

#include "sluice/bake/validate/Validate.h"

namespace sluice::bake::detail {

/// Compares a sparse asset with the reference: a sample of its active (band) voxels for error,
/// sign and Eikonal figures, and a sample of its other grid points (tiles, background) for sign.
/// options.samplePoints in all, nearSurfaceShare of them in the band.
Result<ValidationReport> validateSparse(const format::ColliderAsset& asset,
                                        const CgalReference& reference,
                                        const ValidateOptions& options, Progress* progress);

} // namespace sluice::bake::detail
