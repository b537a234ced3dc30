// Times one mesh baked at several resolutions by the GPU baker, the CGAL reference and OpenVDB's
// meshToSignedDistanceField (band wide enough to fill the whole grid: the dense equivalent).
//
//   bake_bench MESH [RESOLUTION...] [--repeat N] [--gpu-only] [--dump DIR]
//   bake_bench MESH [RESOLUTION...] --whole-process [--repeat N] [--exe SLUICE_BAKE] [--out DIR]
//   (default resolutions: 64 128 256; --whole-process: 64 128)
//
// --whole-process times what a pipeline waits for: the real sluice-bake process, start to exit,
// for --backend gpu and --backend cgal alternately, N times each (default 5), and prints the
// median and range of wall and CPU seconds, the ratio, and the GPU runs' phases (WholeProcess.h).
// --exe defaults to the sluice-bake beside bake_bench.
//
// --dump DIR writes, per resolution, DIR/grid_RES.txt (origin x y z, voxel size, dims x y z) and
// DIR/cgal_RES.f32 (the CGAL field, float32 little-endian, x fastest) for peers outside C++
// (tests/bench/igl_peer.py times libigl on the same points).
//
// Not a ctest test: it prints a table of seconds, ratios and voxels per second, then the same as
// Markdown. Each time is the best of N runs (default 1), in wall-clock seconds and in CPU seconds
// of the whole process (every thread: llvmpipe's, TBB's), which a busy machine distorts less.
// Say where it ran (llvmpipe on a CPU is not a GPU) when quoting its numbers.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "interop/VdbHeaders.h"
SLUICE_VDB_WARNINGS_OFF
#include <openvdb/tools/MeshToVolume.h>
SLUICE_VDB_WARNINGS_ON

#include "WholeProcess.h"
#include "sluice/bake/Grid.h"
#include "sluice/bake/cgal/CgalBaker.h"
#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/gpu/GpuBaker.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/gpu/Context.h"

namespace {

using namespace sluice;
using namespace sluice::bake;
using Clock = std::chrono::steady_clock;

/// CPU time of the whole process so far, every thread [s].
double processCpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

/// Wall-clock and CPU seconds of one run.
struct Timing {
    double wall = 1e300; ///< [s]
    double cpu = 1e300;  ///< [s]
};

/// Runs `work` `repeat` times and keeps the fastest wall time and the least CPU time.
Timing best(int repeat, const std::function<void()>& work) {
    Timing t;
    for (int r = 0; r < repeat; ++r) {
        const double cpu0 = processCpuSeconds();
        const auto wall0 = Clock::now();
        work();
        t.wall = std::min(t.wall, std::chrono::duration<double>(Clock::now() - wall0).count());
        t.cpu = std::min(t.cpu, processCpuSeconds() - cpu0);
    }
    return t;
}

/// OpenVDB's level set on the bake grid, filled densely (band = the whole grid).
openvdb::FloatGrid::Ptr bakeOpenVdb(const ImportedMesh& mesh, const GridSpec& grid) {
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
    return openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*transform, points,
                                                                         triangles, {}, band, band);
}

/// Max |phi_vdb - phi| over the grid [voxels] against `reference`.
double vdbErrorVoxels(const openvdb::FloatGrid& vdb, const GridSpec& grid,
                      const std::vector<float>& reference) {
    openvdb::FloatGrid::ConstAccessor access = vdb.getConstAccessor();
    double maxError = 0.0;
    for (std::uint32_t k = 0; k < grid.dims.z; ++k)
        for (std::uint32_t j = 0; j < grid.dims.y; ++j)
            for (std::uint32_t i = 0; i < grid.dims.x; ++i) {
                const float v = access.getValue(openvdb::Coord(int(i), int(j), int(k)));
                const float r = reference[i + grid.dims.x * (j + std::size_t(grid.dims.y) * k)];
                maxError = std::max(maxError, std::abs(double(v) - r) / grid.voxelSize);
            }
    return maxError;
}

struct Row {
    std::uint32_t resolution = 0;
    double points = 0.0;
    Timing gpu, cgal, vdb;
    GpuBakeStats stats;
    double gpuErrorVoxels = -1.0;     ///< max |phi_gpu - phi_cgal|; < 0 when not measured
    std::uint64_t signMismatches = 0; ///< points where gpu and cgal are non-zero and disagree
    double vdbErrorVoxels = -1.0;
};

struct Args {
    std::vector<std::uint32_t> resolutions;
    const char* meshPath = nullptr;
    int repeat = 0;
    bool gpuOnly = false;
    bool wholeProcess = false;
    const char* dumpDir = nullptr;
    std::string exe;
    std::string outDir;
};

Args parseArgs(int argc, char** argv) {
    Args a;
    a.exe = (std::filesystem::path(argv[0]).parent_path() / "sluice-bake").string();
    a.outDir = (std::filesystem::temp_directory_path() / "bake_bench").string();
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
            a.repeat = std::max(1, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--whole-process") == 0)
            a.wholeProcess = true;
        else if (std::strcmp(argv[i], "--exe") == 0 && i + 1 < argc)
            a.exe = argv[++i];
        else if (std::strcmp(argv[i], "--out") == 0 && i + 1 < argc)
            a.outDir = argv[++i];
        else if (std::strcmp(argv[i], "--dump") == 0 && i + 1 < argc)
            a.dumpDir = argv[++i];
        else if (std::strcmp(argv[i], "--gpu-only") == 0)
            a.gpuOnly = true;
        else if (!a.meshPath)
            a.meshPath = argv[i];
        else
            a.resolutions.push_back(std::uint32_t(std::strtoul(argv[i], nullptr, 10)));
    }
    return a;
}

// The CGAL field and its grid into DIR/grid_RES.txt and DIR/cgal_RES.f32, for plots.
void dumpCgalField(const char* dumpDir, std::uint32_t resolution, const GridSpec& grid,
                   const std::vector<float>& c) {
    const std::string stem = std::string(dumpDir) + "/";
    std::ofstream spec(stem + "grid_" + std::to_string(resolution) + ".txt");
    spec.precision(17);
    spec << grid.origin.x << ' ' << grid.origin.y << ' ' << grid.origin.z << ' ' << grid.voxelSize
         << ' ' << grid.dims.x << ' ' << grid.dims.y << ' ' << grid.dims.z << '\n';
    std::ofstream field(stem + "cgal_" + std::to_string(resolution) + ".f32", std::ios::binary);
    field.write(reinterpret_cast<const char*>(c.data()), std::streamsize(c.size() * sizeof(float)));
    if (!spec || !field)
        std::fprintf(stderr, "bake_bench: could not write to %s\n", dumpDir);
}

// The CGAL and OpenVDB bakes of one row, and the GPU field's error against CGAL's. False (with
// a message) when CGAL fails.
bool measurePeers(const ImportedMesh& mesh, const BakeSettings& settings, const GridSpec& grid,
                  const Args& args, const std::vector<float>& g, Row& row) {
    std::optional<Result<format::ColliderAsset>> cgalAsset;
    row.cgal = best(args.repeat, [&] { cgalAsset = bakeCgal(mesh, settings); });
    if (!*cgalAsset) {
        std::fprintf(stderr, "bake_bench: %s\n", cgalAsset->error().message().c_str());
        return false;
    }
    row.gpuErrorVoxels = 0.0;
    const std::vector<float>& c = (*cgalAsset)->distances;
    for (std::size_t n = 0; n < g.size(); ++n) {
        row.gpuErrorVoxels =
            std::max(row.gpuErrorVoxels, std::abs(double(g[n]) - c[n]) / grid.voxelSize);
        row.signMismatches += g[n] != 0.0f && c[n] != 0.0f && (g[n] < 0.0f) != (c[n] < 0.0f);
    }
    if (args.dumpDir)
        dumpCgalField(args.dumpDir, row.resolution, grid, c);
    openvdb::FloatGrid::Ptr vdb;
    row.vdb = best(args.repeat, [&] { vdb = bakeOpenVdb(mesh, grid); });
    row.vdbErrorVoxels = vdbErrorVoxels(*vdb, grid, c);
    return true;
}

void printRow(const Row& row, bool gpuOnly) {
    const GpuBakeStats& s = row.stats;
    std::printf(
        "%5u %10.0f | %8.3f %8.3f %7.3f %7.3f %7.3f %8llu | %8.3f %8.3f | %8.3f %8.3f "
        "| %8.2f %8.2f | %9.3g | %.2g, %.2g; %llu\n",
        row.resolution, row.points, row.gpu.wall, row.gpu.cpu, s.bvhSeconds, s.distanceNs * 1e-9,
        s.signNs * 1e-9, static_cast<unsigned long long>(s.pendingPoints),
        gpuOnly ? 0.0 : row.cgal.wall, gpuOnly ? 0.0 : row.cgal.cpu, gpuOnly ? 0.0 : row.vdb.wall,
        gpuOnly ? 0.0 : row.vdb.cpu, gpuOnly ? 0.0 : row.cgal.wall / row.gpu.wall,
        gpuOnly ? 0.0 : row.vdb.wall / row.gpu.wall, row.points / row.gpu.wall, row.gpuErrorVoxels,
        row.vdbErrorVoxels, static_cast<unsigned long long>(row.signMismatches));
    std::fflush(stdout);
}

void printTable(const std::vector<Row>& rows) {
    std::printf(
        "\n| resolution | points | gpu s (CPU s) | prepare / distance / sign s | cgal s (CPU s) "
        "| openvdb s (CPU s) | cgal/gpu | vdb/gpu | gpu voxels/s | gpu max err [voxel] "
        "| sign mismatches |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const Row& r : rows)
        std::printf("| %u | %.0f | %.3f (%.2f) | %.3f / %.3f / %.3f | %.2f (%.2f) | %.2f (%.2f) "
                    "| %.1f | %.1f | %.2g | %.1e | %llu |\n",
                    r.resolution, r.points, r.gpu.wall, r.gpu.cpu, r.stats.bvhSeconds,
                    r.stats.distanceNs * 1e-9, r.stats.signNs * 1e-9, r.cgal.wall, r.cgal.cpu,
                    r.vdb.wall, r.vdb.cpu, r.cgal.wall / r.gpu.wall, r.vdb.wall / r.gpu.wall,
                    r.points / r.gpu.wall, r.gpuErrorVoxels,
                    static_cast<unsigned long long>(r.signMismatches));
}

// The in-process rows: the GPU bake at each resolution and, unless --gpu-only, its peers.
// Returns the exit code.
int benchInProcess(Args& args) {
    args.repeat = std::max(args.repeat, 1);
    if (args.resolutions.empty())
        args.resolutions = {64, 128, 256};
    Result<ImportedMesh> mesh = importMesh(args.meshPath, {});
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
    std::printf("mesh %s: %llu triangles; GPU: %s; best of %d run(s)\n", mesh->sourceFile.c_str(),
                static_cast<unsigned long long>(mesh->diagnostics.triangles),
                context->info().renderer.c_str(), args.repeat);
    // Compile the shaders once (llvmpipe compiles on first use; Mesa's shader cache keeps them).
    const Timing warm =
        best(1, [&] { (void)bakeGpu(*mesh, {.grid = {.resolution = 8}}, *context); });
    std::printf("warm-up bake at resolution 8 (shader compilation): %.3f s\n", warm.wall);
    std::printf("%5s %10s | %8s %8s %7s %7s %7s %8s | %8s %8s | %8s %8s | %8s %8s | %9s | %s\n",
                "res", "points", "gpu s", "gpu cpu", "prep s", "dist s", "sign s", "pending",
                "cgal s", "cgal cpu", "vdb s", "vdb cpu", "cgal/gpu", "vdb/gpu", "gpu vox/s",
                "max err vs cgal [voxel]: gpu, vdb; gpu sign mismatches");
    std::vector<Row> rows;
    for (std::uint32_t resolution : args.resolutions) {
        const BakeSettings settings{.grid = {.resolution = resolution}};
        Result<GridSpec> grid = gridFor(mesh->soup.bounds(), settings.grid);
        if (!grid) {
            std::fprintf(stderr, "bake_bench: %s\n", grid.error().message().c_str());
            return 2;
        }
        Row row;
        row.resolution = resolution;
        row.points = double(grid->pointCount());
        std::optional<Result<format::ColliderAsset>> gpuAsset;
        row.gpu = best(args.repeat, [&] {
            gpuAsset = bakeGpu(*mesh, settings, *context, nullptr, {.profile = true}, &row.stats);
        });
        if (!*gpuAsset) {
            std::fprintf(stderr, "bake_bench: %s\n", gpuAsset->error().message().c_str());
            return 4;
        }
        if (!args.gpuOnly &&
            !measurePeers(*mesh, settings, *grid, args, (*gpuAsset)->distances, row))
            return 4;
        printRow(row, args.gpuOnly);
        rows.push_back(row);
    }
    if (!args.gpuOnly)
        printTable(rows);
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    Args args = parseArgs(argc, argv);
    if (!args.meshPath) {
        std::fprintf(stderr, "usage: bake_bench MESH [RESOLUTION...] [--repeat N] [--gpu-only] "
                             "[--dump DIR]\n"
                             "       bake_bench MESH [RESOLUTION...] --whole-process [--repeat N] "
                             "[--exe SLUICE_BAKE] [--out DIR]\n");
        return 2;
    }
    if (args.wholeProcess)
        return sluice::bench::runWholeProcess(
            {.exe = args.exe,
             .mesh = args.meshPath,
             .resolutions =
                 args.resolutions.empty() ? std::vector<std::uint32_t>{64, 128} : args.resolutions,
             .repeat = args.repeat > 0 ? args.repeat : 5,
             .outDir = args.outDir});
    return benchInProcess(args);
}
