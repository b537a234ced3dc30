// Times one mesh baked at several resolutions by the GPU baker, the CGAL reference and OpenVDB's
// meshToSignedDistanceField (band wide enough to fill the whole grid: the dense equivalent).
//
//   bake_bench MESH [RESOLUTION...]     (default resolutions: 64 128)
//
// Not a ctest test: it prints a table of seconds, voxels per second and ratios. Say where it ran
// (llvmpipe on a CPU is not a GPU) when quoting its numbers.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wnon-virtual-dtor"
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#pragma GCC diagnostic pop

#include "sluice/bake/CgalReference.h"
#include "sluice/bake/GpuBaker.h"
#include "sluice/bake/Grid.h"
#include "sluice/bake/MeshImport.h"
#include "sluice/gpu/Context.h"

namespace {

using namespace sluice;
using namespace sluice::bake;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

/// OpenVDB's level set on the bake grid, filled densely (band = the whole grid); returns the
/// seconds it took and the max |phi_vdb - phi| over the grid [voxels] against `reference`.
double bakeOpenVdb(const ImportedMesh& mesh, const GridSpec& grid,
                   const std::vector<float>& reference, double& maxErrorVoxels) {
    std::vector<openvdb::Vec3s> points;
    points.reserve(mesh.soup.positions.size());
    // Index space of the VDB grid = our grid: world = origin + index * voxelSize.
    for (const glm::dvec3& p : mesh.soup.positions)
        points.emplace_back(float(p.x), float(p.y), float(p.z));
    std::vector<openvdb::Vec3I> triangles;
    triangles.reserve(mesh.soup.triangles.size());
    for (const glm::uvec3& t : mesh.soup.triangles)
        triangles.emplace_back(t.x, t.y, t.z);
    auto transform = openvdb::math::Transform::createLinearTransform(grid.voxelSize);
    transform->postTranslate(openvdb::Vec3d(grid.origin.x, grid.origin.y, grid.origin.z));
    const float band = float(std::max(grid.dims.x, std::max(grid.dims.y, grid.dims.z)));
    const auto start = Clock::now();
    openvdb::FloatGrid::Ptr vdb = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
        *transform, points, triangles, {}, band, band);
    const double seconds = secondsSince(start);
    openvdb::FloatGrid::ConstAccessor access = vdb->getConstAccessor();
    maxErrorVoxels = 0.0;
    for (std::uint32_t k = 0; k < grid.dims.z; ++k)
        for (std::uint32_t j = 0; j < grid.dims.y; ++j)
            for (std::uint32_t i = 0; i < grid.dims.x; ++i) {
                const float v = access.getValue(openvdb::Coord(int(i), int(j), int(k)));
                const float r = reference[i + grid.dims.x * (j + std::size_t(grid.dims.y) * k)];
                maxErrorVoxels = std::max(maxErrorVoxels, std::abs(double(v) - r) / grid.voxelSize);
            }
    return seconds;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bake_bench MESH [RESOLUTION...]\n");
        return 2;
    }
    std::vector<std::uint32_t> resolutions;
    for (int a = 2; a < argc; ++a)
        resolutions.push_back(std::uint32_t(std::strtoul(argv[a], nullptr, 10)));
    if (resolutions.empty())
        resolutions = {64, 128};

    Result<ImportedMesh> mesh = importMesh(argv[1], {});
    if (!mesh) {
        std::fprintf(stderr, "bake_bench: %s\n", mesh.error().message().c_str());
        return 2;
    }
    Result<gpu::Context> context = gpu::Context::createHeadless();
    if (!context) {
        std::fprintf(stderr, "bake_bench: %s\n", context.error().message().c_str());
        return 3;
    }
    openvdb::initialize();
    std::printf("mesh %s: %llu triangles; GPU: %s\n", mesh->sourceFile.c_str(),
                static_cast<unsigned long long>(mesh->diagnostics.triangles),
                context->info().renderer.c_str());
    std::printf("%5s %12s | %9s %9s %9s %9s | %9s | %9s %11s | %8s %8s | %s\n", "res", "points",
                "gpu s", "bvh s", "dist s", "sign s", "cgal s", "vdb s", "vdb err vx", "cgal/gpu",
                "vdb/gpu", "gpu voxels/s");
    for (std::uint32_t resolution : resolutions) {
        const BakeSettings settings{.grid = {.resolution = resolution}};
        Result<GridSpec> grid = gridFor(mesh->soup.bounds(), settings.grid);
        if (!grid) {
            std::fprintf(stderr, "bake_bench: %s\n", grid.error().message().c_str());
            return 2;
        }
        GpuBakeStats stats;
        auto start = Clock::now();
        Result<format::ColliderAsset> gpuAsset =
            bakeGpu(*mesh, settings, *context, nullptr, {.profile = true}, &stats);
        const double gpuSeconds = secondsSince(start);
        start = Clock::now();
        Result<format::ColliderAsset> cgalAsset = bakeCgal(*mesh, settings);
        const double cgalSeconds = secondsSince(start);
        if (!gpuAsset || !cgalAsset) {
            std::fprintf(stderr, "bake_bench: %s\n",
                         (!gpuAsset ? gpuAsset.error() : cgalAsset.error()).message().c_str());
            return 4;
        }
        double gpuError = 0.0;
        for (std::size_t n = 0; n < gpuAsset->distances.size(); ++n)
            gpuError = std::max(gpuError,
                                std::abs(double(gpuAsset->distances[n]) - cgalAsset->distances[n]) /
                                    grid->voxelSize);
        double vdbError = 0.0;
        const double vdbSeconds = bakeOpenVdb(*mesh, *grid, cgalAsset->distances, vdbError);
        const double points = double(grid->pointCount());
        std::printf("%5u %12.0f | %9.3f %9.3f %9.3f %9.3f | %9.3f | %9.3f %11.3g | %8.2f %8.2f | "
                    "%.3g (gpu vs cgal max err %.2g voxel)\n",
                    resolution, points, gpuSeconds, stats.bvhSeconds, stats.distanceNs * 1e-9,
                    stats.signNs * 1e-9, cgalSeconds, vdbSeconds, vdbError,
                    cgalSeconds / gpuSeconds, vdbSeconds / gpuSeconds, points / gpuSeconds,
                    gpuError);
        std::fflush(stdout);
    }
    return 0;
}
