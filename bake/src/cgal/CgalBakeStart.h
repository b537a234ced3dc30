// Private: what the CGAL bakes, dense and sparse, start from: the grid and the reference.
#pragma once

#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/Grid.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// The grid of a CGAL bake and the exact reference that fills it.
struct CgalBakeStart {
    GridSpec grid;
    CgalReference reference;
};

/// `grid` (gridFor's or sparseGridFor's answer), then the reference of the mesh with `sign`.
/// Errors: the grid's first, then those of CgalReference::build.
Result<CgalBakeStart> startCgalBake(const ImportedMesh& mesh, Result<GridSpec> grid, SignMode sign);

} // namespace sluice::bake
