// Times OpenVDB's meshToLevelSet on a mesh at a resolution and band, for comparison with
// `sluice-bake bake --sparse` (same voxel size: the longest side of the mesh box / resolution).
//
//   sparse_bench MESH --resolution R [--band N]
//
// Prints one JSON line: seconds, active voxels, the grid's memory and the process's peak
// resident memory. One mesh per process, so the peak is this bake's. Not a ctest test; say where
// it ran (a loaded 2-core machine is not a workstation) when quoting its numbers.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "interop/VdbHeaders.h"
SLUICE_VDB_WARNINGS_OFF
#include <openvdb/tools/MeshToVolume.h>
SLUICE_VDB_WARNINGS_ON

#include "sluice/bake/import/MeshImport.h"

int main(int argc, char** argv) {
    using namespace sluice;
    if (argc < 2) {
        std::fprintf(stderr, "usage: sparse_bench MESH --resolution R [--band N]\n");
        return 2;
    }
    std::string path = argv[1];
    int resolution = 256;
    double band = 3.0;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (std::strcmp(argv[i], "--resolution") == 0)
            resolution = std::atoi(argv[i + 1]);
        else if (std::strcmp(argv[i], "--band") == 0)
            band = std::atof(argv[i + 1]);
    }
    auto mesh = bake::importMesh(path, {});
    if (!mesh) {
        std::fprintf(stderr, "%s\n", mesh.error().message().c_str());
        return 2;
    }
    const auto box = mesh->soup.bounds();
    const glm::dvec3 side = box.hi - box.lo;
    const double h = std::max(side.x, std::max(side.y, side.z)) / resolution;

    openvdb::initialize();
    const auto start = std::chrono::steady_clock::now();
    auto transform = openvdb::math::Transform::createLinearTransform(h);
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    for (const glm::dvec3& p : mesh->soup.positions)
        points.emplace_back(float(p.x), float(p.y), float(p.z)); // world space
    for (const glm::uvec3& t : mesh->soup.triangles)
        triangles.emplace_back(t.x, t.y, t.z);
    auto grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles,
                                                                   float(band));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::printf("{\"mesh\": \"%s\", \"resolution\": %d, \"band\": %g, \"voxelSize\": %.9g, "
                "\"seconds\": %.3f, \"activeVoxels\": %llu, \"gridBytes\": %llu, "
                "\"peakRssBytes\": %llu}\n",
                path.c_str(), resolution, band, h, seconds,
                (unsigned long long)grid->activeVoxelCount(), (unsigned long long)grid->memUsage(),
                (unsigned long long)usage.ru_maxrss * 1024ull);
    return 0;
}
