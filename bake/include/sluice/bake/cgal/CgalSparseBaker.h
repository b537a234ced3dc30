// Baking a sparse collider asset on the CPU with the CGAL reference: exact values in the band.
#pragma once

#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/bake/sparse/SparseBaker.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// Bakes a sparse collider on the CPU with the CGAL reference (backend "cgal"): planSparse with
/// the AABB tree's distance, exact signed distances (the reference's sign method) at every
/// brick voxel, one signed sample per uniform block. With `showProgress`, a bar over the brick
/// voxels on stderr. Errors from sparseGridFor and CgalReference::build; SizeOverflow when out of
/// memory.
Result<format::ColliderAsset> bakeSparseCgal(const ImportedMesh& mesh, const BakeSettings& settings,
                                             const SparseSettings& sparse,
                                             bool showProgress = false,
                                             SparseBakeStats* stats = nullptr);

} // namespace sluice::bake
