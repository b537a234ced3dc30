// Checking any collider asset against the exact CGAL reference.
#pragma once

#include <cstdint>
#include <string>

#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

struct ValidateOptions {
    std::uint64_t maxFullPoints = 2'000'000; ///< above this many grid points, sample instead
    std::uint64_t samplePoints = 1'000'000;  ///< sample size for large grids
    double nearSurfaceShare = 0.5;           ///< share of the sample within 2 voxels of the surface
    double surfaceBand = 1e-4;               ///< [voxels] sign mismatches this close are ignored
    SignMode sign = SignMode::Auto;          ///< reference sign method
    std::uint64_t seed = 1;                  ///< sampling seed (reports are reproducible)
};

/// What `sluice-bake validate` reports. Errors are in voxel units.
struct ValidationReport {
    format::ValidationFigures figures;
    bool sampled = false;               ///< true when a stratified sample was used
    std::uint64_t signComparedPoints = 0; ///< points outside the surface band
    double signMismatchPercent = 0.0;
    format::SignMethod referenceSign = format::SignMethod::Parity;
    std::uint64_t bandPoints = 0; ///< sparse: active voxels checked (error, sign)
    std::uint64_t tilePoints = 0; ///< sparse: inactive grid points checked (sign only)
};

/// Recomputes the reference at every grid point (or a stratified sample with a near-surface
/// share for grids over maxFullPoints) and compares. Eikonal statistics use central differences
/// of the asset at interior grid points. A sparse asset is always sampled: samplePoints in all,
/// nearSurfaceShare of them among its band (active) voxels for error and sign, the rest uniform
/// over its other grid points (tiles, background) for sign only.
Result<ValidationReport> validate(const format::ColliderAsset& asset, const ImportedMesh& mesh,
                                  const ValidateOptions& options, Progress* progress = nullptr);

} // namespace sluice::bake
