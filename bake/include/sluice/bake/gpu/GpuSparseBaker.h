// Baking a sparse collider asset on the GPU: the GPU bake's passes over the band's bricks.
#pragma once

#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/gpu/GpuBaker.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/bake/sparse/SparseBaker.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"
#include "sluice/gpu/Context.h"

namespace sluice::bake {

/// Bakes a sparse collider on the GPU (backend "gpu"): the asset bakeSparseCgal makes, from the
/// GPU bake's passes over lists instead of the whole grid. The culling's distance queries run on
/// the GPU (block centres, understated by their float rounding bound so no band brick is
/// lost); each band brick gets the exact distance and the sign of every voxel as the dense GPU
/// bake computes them (coarse points of its own, empty balls, the fast winding number, the
/// exact sum near the decision); each uniform block gets the sign of its centre. Bricks go
/// through the GPU in fixed-size batches, so GPU memory does not grow with the grid. With
/// `showProgress`, a bar over the brick voxels on stderr. Deterministic. Needs `context`
/// current. Errors: those of sparseGridFor and bakeGpu.
Result<format::ColliderAsset>
bakeSparseGpu(const ImportedMesh& mesh, const BakeSettings& settings, const SparseSettings& sparse,
              gpu::Context& context, bool showProgress = false, const GpuBakeOptions& options = {},
              GpuBakeStats* stats = nullptr, SparseBakeStats* sparseStats = nullptr);

} // namespace sluice::bake
