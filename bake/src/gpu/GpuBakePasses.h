// What the dense and the sparse GPU bakes share: their opening (the soup, the BVH on the GPU,
// the programs of a point layout, shaders/glsl/SdfBakeGlsl.h), the slabs of the fine pass and
// the sign lists between them. GpuBaker.cpp describes the passes; GpuSparseBaker.cpp runs them
// over brick lists.
#pragma once

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "BakeErrors.h"
#include "gpu/Bvh.h"
#include "gpu/GpuSoup.h"
#include "sluice/bake/Grid.h"
#include "sluice/bake/gpu/GpuBaker.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/BufferTexture.h"
#include "sluice/gpu/Gl.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/gpu/Program.h"

namespace sluice::bake {

/// "N MiB", rounded up.
std::string mib(std::uint64_t bytes);

/// One storage buffer of a bake: where it goes, its size [bytes], its debug label and binding.
struct StorageAlloc {
    gpu::Buffer* buffer;
    std::uint64_t bytes;
    const char* label;
    int binding;
};
/// Creates each buffer and binds it to its binding; the first failure's error.
Result<void> createStorage(std::span<const StorageAlloc> allocs);

/// [bytes] The BVH's two node textures (an upper bound: fewer than two nodes per triangle) and
/// the triangle texture.
std::uint64_t bvhNodeBytes(std::uint64_t triangles);
std::uint64_t bvhTriangleBytes(std::uint64_t triangles);

/// SizeOverflow when `triangles` need buffer textures over this GL's limit (or
/// options.maxBufferBytes), naming `sourceFile`.
Result<void> checkBvhFits(const std::string& sourceFile, std::uint64_t triangles,
                          const GpuBakeOptions& options);

/// The BVH and its triangles as buffer textures bound to their units (shared/SdfBake.h).
struct GpuBvh {
    gpu::Buffer distanceNodes, windingNodes, triangles;
    std::vector<gpu::BufferTexture> textures; ///< distance nodes, winding nodes, triangles

    std::uint64_t bytes() const {
        return distanceNodes.size() + windingNodes.size() + triangles.size();
    }
};

/// Which points the bake's programs compute (shaders/glsl/SdfBakeGlsl.h).
enum class BakeLayout {
    Dense,  ///< the whole grid
    Sparse, ///< the bricks of a list (SDF_SPARSE)
    Points, ///< query points: distance and sign only (SDF_POINTS)
};

/// The programs of the bake for one layout, compiled from the embedded sources. Points has only
/// `coarse` and `coarseSign`; the others stay empty.
struct BakePrograms {
    gpu::Program coarse;     ///< sdf_coarse.comp
    gpu::Program distance;   ///< sdf_distance.comp
    gpu::Program coarseSign; ///< sdf_sign.comp with SDF_SIGN_COARSE
    gpu::Program sign;       ///< sdf_sign.comp over the pending list
    gpu::Program exactSign;  ///< sdf_sign.comp with SDF_SIGN_EXACT, over the verify list
};

/// What both GPU bakes build before their own buffers: the soup prepared for the GPU, the BVH on
/// the CPU and on the GPU, and the programs of the layouts the bake runs.
struct BakeSetup {
    GpuSoup soup;
    Bvh bvh;
    std::vector<BakePrograms> programs; ///< one per layout, in the order asked for
    GpuBvh gpuBvh;
};

/// The opening of a GPU bake: prepares the soup (prepareGpuSoup, then its triangles in
/// grid-relative voxels; lap "gpu: prepare the soup"), hands its triangle count to `fits` before
/// anything big is built, builds the BVH (its figures in `stats`, bvhSeconds from the start; lap
/// "gpu: BVH build"), compiles the programs of `layouts` with the uniforms that stay the same for
/// the whole bake (lap "gpu: compile and link programs") and uploads the BVH as buffer textures
/// bound to their units. The first error of those steps.
Result<BakeSetup> setUpBake(const ImportedMesh& mesh, const GridSpec& grid, SignMode sign,
                            std::initializer_list<BakeLayout> layouts,
                            const std::function<Result<void>(std::uint64_t triangles)>& fits,
                            const GpuBakeOptions& options, GpuBakeStats& stats);

/// What the passes of one bake share: the dispatch limits, the timers (profile only) and the
/// statistics they add to.
struct BakePasses {
    GpuBakeStats& stats;
    std::uint64_t maxGroups = 0;   ///< work groups per dispatch
    std::uint64_t exactGroups = 0; ///< work groups per dispatch of the exact winding number
    std::optional<gpu::GpuTimer> distanceTimer, signTimer;

    /// A distance pass over `groups` work groups, timed with the distance passes.
    void distance(const gpu::Program& program, glm::uvec3 groups);
    /// A sign pass over `items` list entries, `groupsPerDispatch` work groups per dispatch,
    /// timed with the sign passes.
    void sign(const gpu::Program& program, std::uint32_t items, std::uint64_t groupsPerDispatch);
    /// The GPU time of the passes into the statistics (profile only; waits for the queries).
    void readTimes();
};
BakePasses makePasses(GpuBakeStats& stats, const GpuBakeOptions& options,
                      std::uint32_t triangleCount);

/// The sign lists between the slabs of the fine pass (shared/SdfBake.h, PendingHeader).
struct SignLists {
    gpu::Buffer& pending; ///< blocks of the slab with points still without a sign
    gpu::Buffer& verify;  ///< points whose fast winding number is too near the decision
};

/// [bytes] The lists' room for `blocks` blocks of a slab.
std::uint64_t pendingBytes(std::uint64_t blocks);
std::uint64_t verifyBytes(std::uint64_t blocks);

/// Passes 3 and 4 in slabs: `layers` layers of work groups, each `layerGroups` (dense: the z
/// layers of the grid's groups; sparse: single groups along the brick list, `alongX`). Each slab
/// runs the fine distance pass (`groupBegin` = its first layer), then the fast winding number of
/// its pending blocks and the exact one of the points too near the decision, reading back the two
/// list headers. The first slab has `firstLayers` layers; later ones are sized from the measured
/// rate to take about a tenth of a second, up to `maxLayers` (the lists' room). `progress` gets
/// `pointsOf(first, end)` after each slab. The split does not change a bit of the result.
struct SlabPlan {
    glm::uvec2 layerGroups{1, 1};
    std::uint32_t layers = 0;
    std::uint32_t firstLayers = 1;
    std::uint32_t maxLayers = 1;
    bool alongX = false;
    std::function<std::uint64_t(std::uint32_t, std::uint32_t)> pointsOf;
};
void runSlabs(BakePasses& passes, const BakePrograms& programs, const SignLists& lists,
              const SlabPlan& plan, Progress* progress);

} // namespace sluice::bake
