// Baking a collider asset on the GPU (any OpenGL 4.5 compute implementation, headless EGL).
#pragma once

#include <cstdint>

#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/bake/jobs/PhaseLog.h"
#include "sluice/bake/jobs/Progress.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"
#include "sluice/gpu/Context.h"
#include "sluice/gpu/ProgramCache.h"

namespace sluice::bake {

/// Knobs of the GPU bake that do not change the result beyond float rounding.
struct GpuBakeOptions {
    /// Far-field accuracy of the fast winding number: a BVH node is summarized by its dipole
    /// when the query is farther than beta times the node's radius (Barill et al. 2018, sec. 3.2).
    double beta = 2.0;
    /// An approximate winding number within this of the decision value (0.5, or a half-integer
    /// for parity) is recomputed exactly over every triangle.
    double verifyBand = 0.2;
    /// Largest single GPU buffer [bytes]; 0: the context's GL_MAX_SHADER_STORAGE_BLOCK_SIZE.
    /// Lower it to test the limit checks.
    std::uint64_t maxBufferBytes = 0;
    /// Most work groups per dispatch, so no dispatch runs for long (Program::dispatchChunked).
    std::uint64_t maxGroupsPerDispatch = 1024;
    /// Bricks a sparse bake sends through the passes at once (its GPU buffers hold one batch):
    /// 8192 bricks, 4M grid points. Lower it to test batching; the result does not change.
    std::uint32_t sparseBricksPerBatch = 8192;
    /// Measure the GPU passes with timer queries (GpuBakeStats::distanceNs, signNs).
    bool profile = false;
    /// Where the compiled programs are cached between processes, if anywhere (opened for
    /// `context`); without one every program is compiled.
    gpu::ProgramCache* programCache = nullptr;
    /// Where the bake laps its phases (soup, BVH, programs, upload, passes, readback, asset), if
    /// anywhere: the caller's timeline of the whole process.
    PhaseLog* phases = nullptr;
};

/// What a GPU bake did, for sluice-bake --profile and benchmarks.
struct GpuBakeStats {
    std::uint64_t triangles = 0;      ///< non-degenerate triangles in the BVH
    std::uint64_t nodes = 0;          ///< BVH nodes
    std::uint32_t depth = 0;          ///< BVH levels below the root
    double bvhSeconds = 0.0;          ///< [s] CPU time to prepare the soup and build the BVH
    std::uint32_t dispatches = 0;     ///< compute dispatches issued, every pass
    std::uint64_t distanceNs = 0;     ///< [ns] GPU time of the distance passes, coarse and fine
                                      ///< (profile only)
    std::uint64_t signNs = 0;         ///< [ns] GPU time of the sign passes (profile only)
    std::uint64_t gpuBytes = 0;       ///< [bytes] GPU buffers allocated
    std::uint64_t pendingPoints = 0;  ///< grid points whose winding number was computed (the
                                      ///< others took the sign of a coarse point)
    std::uint64_t verifiedPoints = 0; ///< of those, points near the decision value that needed
                                      ///< the exact sum over every triangle
};

/// Bakes the mesh on the GPU into a collider asset with the same grid and provenance as bakeCgal
/// (backend "gpu"). Distances are exact closest-point distances through a BVH, computed in float
/// in grid-relative voxel units; the sign comes from the fast winding number (inside where
/// w > 0.5). "parity" (asked for, or chosen by auto for closed meshes that do not intersect
/// themselves) orients the closed soup consistently (as the CGAL path does) and takes inside
/// where the winding number rounds to an odd integer, which for a closed oriented surface equals
/// ray parity; a soup that cannot be oriented into a closed mesh falls back to the winding
/// number, as on the CGAL path. On a closed soup (a cycle, whose winding number is an integer off
/// the surface) the winding number is only evaluated at every 4th grid point along each axis and
/// at the points none of their empty balls (radius |phi|) covers; the others take the sign of a
/// ball that holds them. Deterministic: the same input gives the same bytes.
/// Needs `context` current. Errors: those of gridFor, EmptyMesh, InvalidArgument (parity on an
/// open mesh), SizeOverflow (a buffer over the GL limit), GpuOutOfMemory, ShaderCompile/Link.
Result<format::ColliderAsset> bakeGpu(const ImportedMesh& mesh, const BakeSettings& settings,
                                      gpu::Context& context, Progress* progress = nullptr,
                                      const GpuBakeOptions& options = {},
                                      GpuBakeStats* stats = nullptr);

} // namespace sluice::bake
