// Baking a dense collider asset on the CPU with the CGAL reference.
#pragma once

#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/bake/jobs/Progress.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// Bakes the mesh on the CPU with CGAL into a collider asset with full provenance (backend
/// "cgal"). Errors from gridFor and CgalReference::build.
Result<format::ColliderAsset> bakeCgal(const ImportedMesh& mesh, const BakeSettings& settings,
                                       Progress* progress = nullptr);

} // namespace sluice::bake
