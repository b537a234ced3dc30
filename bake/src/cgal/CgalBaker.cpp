// Baking a collider asset on the CPU with the CGAL reference, with full provenance.
#include "sluice/bake/cgal/CgalBaker.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "BakeErrors.h"
#include "cgal/CgalBakeStart.h"
#include "import/MeshMass.h"

namespace sluice::bake {

namespace {
/// Grid points handed to the reference per call [points]: bounds the memory for positions
/// (24 bytes each) while keeping every core busy.
constexpr std::uint64_t kPointsPerBatch = std::uint64_t(1) << 20;

Result<format::ColliderAsset> bakeChecked(const ImportedMesh& mesh, const BakeSettings& settings,
                                          Progress* progress) {
    Result<CgalBakeStart> start =
        startCgalBake(mesh, gridFor(mesh.soup.bounds(), settings.grid), settings.sign);
    if (!start)
        return start.error();
    const CgalReference& reference = start->reference;

    format::ColliderAsset asset;
    asset.meta = bakeProvenance(mesh, start->grid, settings, "cgal", reference.signMethod());
    format::ColliderMeta& meta = asset.meta;

    // Whole z-slices per batch; x runs fastest, as in the asset, so neighbouring points follow
    // each other and the reference can carry its winding number along the rows.
    const std::uint64_t slice = std::uint64_t(meta.dims.x) * meta.dims.y;
    const std::uint32_t slicesPerBatch =
        std::uint32_t(std::clamp<std::uint64_t>(kPointsPerBatch / slice, 1, meta.dims.z));
    asset.distances.resize(asset.pointCount());
    std::vector<glm::dvec3> points;
    for (std::uint32_t k0 = 0; k0 < meta.dims.z; k0 += slicesPerBatch) {
        const std::uint32_t k1 = std::min(meta.dims.z, k0 + slicesPerBatch);
        points.clear();
        for (std::uint32_t k = k0; k < k1; ++k)
            for (std::uint32_t j = 0; j < meta.dims.y; ++j)
                for (std::uint32_t i = 0; i < meta.dims.x; ++i)
                    points.push_back(asset.pointPosition(i, j, k));
        const std::vector<double> phi = reference.signedDistances(points, progress);
        std::transform(phi.begin(), phi.end(), asset.distances.begin() + std::ptrdiff_t(k0 * slice),
                       [](double v) { return float(v); });
    }
    return asset;
}
} // namespace

Result<CgalBakeStart> startCgalBake(const ImportedMesh& mesh, Result<GridSpec> grid,
                                    SignMode sign) {
    if (!grid)
        return grid.error();
    Result<CgalReference> reference = CgalReference::build(mesh.soup, mesh.diagnostics, sign);
    if (!reference)
        return reference.error();
    return CgalBakeStart{*grid, std::move(*reference)};
}

format::ColliderMeta bakeProvenance(const ImportedMesh& mesh, const GridSpec& grid,
                                    const BakeSettings& settings, const char* backend,
                                    format::SignMethod signUsed) {
    format::ColliderMeta meta;
    meta.dims = grid.dims;
    meta.origin = grid.origin;
    meta.voxelSize = grid.voxelSize;
    meta.storage = settings.storage;
    meta.signConvention = -1;
    meta.sourceFile = mesh.sourceFile;
    meta.sourceHash = mesh.sourceHash;
    meta.bake.backend = backend;
    meta.bake.resolution = settings.grid.voxelSize > 0.0 ? 0 : settings.grid.resolution;
    meta.bake.padding = settings.grid.padding;
    meta.bake.signMode = signModeName(settings.sign);
    meta.bake.signUsed = signUsed;
    meta.bake.scale = settings.scale;
    meta.toolVersion = std::string("sluice-bake ") + SLUICE_VERSION;
    meta.mesh = mesh.diagnostics;
    // The soup is already in world units after the import scale, the frame of the grid.
    meta.meshMass = closedMeshMass(mesh.soup, mesh.diagnostics);
    return meta;
}

Result<format::ColliderAsset> bakeCgal(const ImportedMesh& mesh, const BakeSettings& settings,
                                       Progress* progress) {
    return withCgalErrors(mesh, [&] { return bakeChecked(mesh, settings, progress); });
}

} // namespace sluice::bake
