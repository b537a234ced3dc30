// Baking a collider asset on the GPU: CPU BVH, closest-point pass, fast-winding-number sign pass.
//
// The soup is prepared exactly as the CGAL reference prepares it (degenerate triangles left out
// with CGAL's exact collinearity test; a closed soup wound inward turned outward; parity meshes
// oriented with orient_polygon_soup), then moved into grid-relative voxel coordinates, where
// grid point (i, j, k) is the float (i, j, k) and every coordinate is no larger than the grid.
// The grid is processed in z-slabs; each slab runs the distance pass, then the sign pass, each
// split into dispatches of a bounded number of work groups.
#include "sluice/bake/GpuBaker.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <glm/geometric.hpp>

#include "BoundaryChain.h"
#include "Bvh.h"
#include "sluice/bake/BakeShaders.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Gl.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/gpu/Program.h"

namespace sluice::bake {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

/// Grid points per slab [points]: between two slabs the CPU waits for the GPU and reports
/// progress, so this bounds the time between progress updates.
constexpr std::uint64_t kPointsPerSlab = std::uint64_t(1) << 18;

Point toPoint(const glm::dvec3& p) {
    return Point(p.x, p.y, p.z);
}

/// True when every edge's uses in one direction cancel its uses in the other: the soup is a
/// cycle, whose winding number is an integer everywhere off it.
bool isCycle(const std::vector<std::array<std::size_t, 3>>& polygons) {
    return boundaryChain(polygons).empty();
}

struct PreparedSoup {
    std::vector<glm::dvec3> points;
    std::vector<std::array<std::size_t, 3>> triangles; ///< non-degenerate, oriented
    format::SignMethod method = format::SignMethod::Winding;
};

/// The triangles the bake uses, oriented as the CGAL reference orients them.
Result<PreparedSoup> prepare(const TriangleSoup& soup, const format::MeshDiagnostics& diagnostics,
                             SignMode mode) {
    Result<format::SignMethod> method = chooseSignMethod(diagnostics, mode);
    if (!method)
        return method.error();
    PreparedSoup out;
    out.method = *method;
    out.points = soup.positions;
    std::vector<std::array<std::size_t, 3>> faces; // three distinct corners
    faces.reserve(soup.triangles.size());
    for (const glm::uvec3& t : soup.triangles)
        if (t.x != t.y && t.y != t.z && t.z != t.x)
            faces.push_back({t.x, t.y, t.z});

    if (out.method == format::SignMethod::Parity) {
        // As CGAL's Side_of_triangle_mesh needs: one consistent orientation of the closed
        // surface. Zero-area faces stay in for this (without them a closed mesh has holes).
        std::vector<Point> points;
        points.reserve(out.points.size());
        for (const glm::dvec3& p : out.points)
            points.push_back(toPoint(p));
        std::vector<std::array<std::size_t, 3>> oriented = faces;
        namespace PMP = CGAL::Polygon_mesh_processing;
        (void)PMP::orient_polygon_soup(points, oriented);
        if (PMP::is_polygon_soup_a_polygon_mesh(oriented) && isCycle(oriented)) {
            out.points.clear();
            for (const Point& p : points)
                out.points.push_back({p.x(), p.y(), p.z()});
            faces = std::move(oriented);
        } else {
            out.method = format::SignMethod::Winding;
        }
    }

    for (const auto& t : faces)
        if (!CGAL::collinear(toPoint(out.points[t[0]]), toPoint(out.points[t[1]]),
                             toPoint(out.points[t[2]])))
            out.triangles.push_back(t);
    if (out.triangles.empty())
        return fail(ErrorCode::EmptyMesh, "the mesh has no triangle of non-zero area");

    // A closed soup wound inward would give w = -1 inside; turn it outward, as the reference does.
    if (isCycle(out.triangles)) {
        const Box box = soup.bounds();
        const glm::dvec3 center = 0.5 * (box.lo + box.hi);
        double volume = 0.0;
        for (const auto& t : out.triangles)
            volume += glm::dot(out.points[t[0]] - center,
                               glm::cross(out.points[t[1]] - center, out.points[t[2]] - center));
        if (volume < 0.0)
            for (auto& t : out.triangles)
                std::swap(t[1], t[2]);
    }
    return out;
}

std::string mib(std::uint64_t bytes) {
    return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}

Result<format::ColliderAsset> bakeChecked(const ImportedMesh& mesh, const BakeSettings& settings,
                                          gpu::Context& context, Progress* progress,
                                          const GpuBakeOptions& options, GpuBakeStats& stats) {
    Result<GridSpec> grid = gridFor(mesh.soup.bounds(), settings.grid);
    if (!grid)
        return grid.error();
    const auto cpuStart = std::chrono::steady_clock::now();
    Result<PreparedSoup> soup = prepare(mesh.soup, mesh.diagnostics, settings.sign);
    if (!soup)
        return soup.error();

    // Grid-relative voxel coordinates: the float (i, j, k) is grid point (i, j, k) exactly.
    std::vector<BvhInputTriangle> input;
    input.reserve(soup->triangles.size());
    const double inverseVoxel = 1.0 / grid->voxelSize;
    auto toVoxels = [&](std::size_t v) { return (soup->points[v] - grid->origin) * inverseVoxel; };
    for (const auto& t : soup->triangles)
        input.push_back({toVoxels(t[0]), toVoxels(t[1]), toVoxels(t[2])});

    // Check sizes before building anything big.
    const std::uint64_t maxBuffer =
        options.maxBufferBytes > 0 ? options.maxBufferBytes : context.info().maxSsboBytes;
    const std::uint64_t gridBytes = grid->pointCount() * sizeof(float);
    const std::uint64_t triangleBytes = input.size() * sizeof(shared::BvhTriangle);
    // Median splits stop at 2..kBvhLeafSize triangles per leaf, so there are at most n / 2
    // leaves and fewer than n nodes: an upper bound.
    const std::uint64_t nodeBytes =
        std::max<std::uint64_t>(input.size(), 1) * sizeof(shared::BvhNode);
    if (gridBytes > maxBuffer)
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": a grid of " + std::to_string(grid->dims.x) + " x " +
                        std::to_string(grid->dims.y) + " x " + std::to_string(grid->dims.z) +
                        " points needs a " + mib(gridBytes) +
                        " GPU buffer, over this GPU's largest storage buffer (" + mib(maxBuffer) +
                        "); use a coarser resolution or --backend cgal");
    if (triangleBytes > maxBuffer || nodeBytes > maxBuffer)
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": " + std::to_string(input.size()) +
                        " triangles need GPU buffers over this GPU's largest storage buffer (" +
                        mib(maxBuffer) + "); simplify the mesh or use --backend cgal");
    const std::uint64_t totalBytes = gridBytes + triangleBytes + nodeBytes;
    if (const auto& available = context.info().gpuMemoryAvailableBytes;
        available && totalBytes > *available)
        return fail(ErrorCode::GpuOutOfMemory,
                    mesh.sourceFile + ": the bake needs " + mib(totalBytes) +
                        " of GPU memory and " + mib(*available) +
                        " are free; use a coarser resolution or --backend cgal");

    const Bvh bvh = buildBvh(input);
    stats.triangles = bvh.triangles.size();
    stats.nodes = bvh.nodes.size();
    stats.depth = bvh.depth;
    stats.bvhSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - cpuStart).count();

    Result<gpu::Program> distance =
        gpu::Program::compute("sdf_distance.comp", shaders::shaderSource("sdf_distance.comp"));
    if (!distance)
        return distance.error();
    Result<gpu::Program> sign =
        gpu::Program::compute("sdf_sign.comp", shaders::shaderSource("sdf_sign.comp"));
    if (!sign)
        return sign.error();
    Result<gpu::Buffer> nodes = gpu::Buffer::createFrom(bvh.nodes, "bake BVH nodes");
    if (!nodes)
        return nodes.error();
    Result<gpu::Buffer> triangles = gpu::Buffer::createFrom(bvh.triangles, "bake triangles");
    if (!triangles)
        return triangles.error();
    Result<gpu::Buffer> phi = gpu::Buffer::create(gridBytes, "bake distances");
    if (!phi)
        return phi.error();
    stats.gpuBytes = nodes->size() + triangles->size() + phi->size();
    nodes->bindStorage(shared::kBakeNodesBinding);
    triangles->bindStorage(shared::kBakeTrianglesBinding);
    phi->bindStorage(shared::kBakeDistanceBinding);

    const glm::uvec3 dims = grid->dims;
    for (const gpu::Program* program : {&*distance, &*sign})
        program->set("dims", dims);
    distance->set("bvhDepth", bvh.depth);
    sign->set("beta", float(options.beta));
    sign->set("verifyBand", float(options.verifyBand));
    sign->set("parity", std::uint32_t(soup->method == format::SignMethod::Parity ? 1 : 0));

    std::optional<gpu::GpuTimer> distanceTimer, signTimer;
    if (options.profile) {
        distanceTimer.emplace();
        signTimer.emplace();
    }
    // Whole multiples of the group depth per slab, so only the last slab has partial groups.
    const std::uint64_t slice = std::uint64_t(dims.x) * dims.y;
    const std::uint32_t local = shared::kBakeLocalSize;
    const std::uint32_t slabDepth = std::uint32_t(std::clamp<std::uint64_t>(
        kPointsPerSlab / slice / local * local, local, (dims.z + local - 1) / local * local));
    for (std::uint32_t k0 = 0; k0 < dims.z; k0 += slabDepth) {
        const std::uint32_t k1 = std::min(dims.z, k0 + slabDepth);
        const glm::uvec3 groups =
            gpu::groupCount(glm::uvec3(dims.x, dims.y, k1 - k0), glm::uvec3(local));
        for (const gpu::Program* program : {&*distance, &*sign}) {
            program->set("sliceBegin", k0);
            program->set("sliceEnd", k1);
        }
        if (distanceTimer)
            distanceTimer->begin();
        stats.dispatches += distance->dispatchChunked(groups, options.maxGroupsPerDispatch);
        if (distanceTimer)
            distanceTimer->end();
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        if (signTimer)
            signTimer->begin();
        stats.dispatches += sign->dispatchChunked(groups, options.maxGroupsPerDispatch);
        if (signTimer)
            signTimer->end();
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        if (progress) {
            glFinish();
            progress->add(std::uint64_t(k1 - k0) * slice);
        }
    }
    const std::vector<float> voxels = phi->download<float>();
    if (distanceTimer) {
        (void)distanceTimer->elapsedNs();
        (void)signTimer->elapsedNs();
        stats.distanceNs = distanceTimer->totalNs();
        stats.signNs = signTimer->totalNs();
    }

    format::ColliderAsset asset;
    asset.meta = bakeProvenance(mesh, *grid, settings, "gpu", soup->method);
    // Voxels to world units in double, so the only float rounding is the GPU's and the last one.
    asset.distances.resize(voxels.size());
    std::transform(voxels.begin(), voxels.end(), asset.distances.begin(),
                   [&](float v) { return float(double(v) * grid->voxelSize); });
    return asset;
}
} // namespace

Result<format::ColliderAsset> bakeGpu(const ImportedMesh& mesh, const BakeSettings& settings,
                                      gpu::Context& context, Progress* progress,
                                      const GpuBakeOptions& options, GpuBakeStats* stats) {
    context.makeCurrent();
    GpuBakeStats local;
    // CGAL (orientation) reports broken preconditions and allocation failures by throwing.
    try {
        Result<format::ColliderAsset> asset =
            bakeChecked(mesh, settings, context, progress, options, stats ? *stats : local);
        return asset;
    } catch (const std::bad_alloc&) {
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": out of memory while baking; use a coarser grid");
    } catch (const std::exception& e) {
        return fail(ErrorCode::Unsupported, mesh.sourceFile +
                                                ": preparing this mesh for the GPU bake failed (" +
                                                e.what() + ")");
    }
}

} // namespace sluice::bake
