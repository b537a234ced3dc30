// The collision pass's collider lookups, dense against sparse, on the same grid and the same
// points: what a scene pays for baking its collider --sparse.
//
//   collider_bench SCENE DENSE.slc SPARSE.slc [--steps N] [--repeat R]
//
// SCENE's one collider is replaced by each asset in turn. The scene runs N steps (default 30)
// with the dense asset; the particles' positions then are the points: where the solver's
// collision pass samples the collider. Then, alternating dense and sparse R times (default 15),
// the bench times (GPU timer queries) one pass of shaders/render/collider_probe.comp over those
// points, which samples phi and its gradient exactly as collide() does (sampleCollider), and one
// solver step of the scene from the same state (the whole step, lookups included). It prints
// the median and range of each and the sparse / dense ratios.
//
// The two assets must share their grid (origin, voxel size, dims): bake the dense one with the
// padding the sparse one uses (band + 1), e.g. for the tank scene
//   sluice-bake bake assets/tank.obj -o dense.slc --backend cgal --voxel-size 0.0075 --padding 5
//   sluice-bake bake assets/tank.obj -o sparse.slc --backend cgal --voxel-size 0.0075 --sparse
//   --band 4
// Not a ctest test. Say where it ran (llvmpipe on a CPU is not a GPU) when quoting its numbers.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "BenchFigures.h"
#include "shared/Pbf.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/BufferTexture.h"
#include "sluice/gpu/Context.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/gpu/Program.h"
#include "sluice/gpu/colliders/ColliderRecord.h"
#include "sluice/rt/RuntimeShaders.h"
#include "sluice/rt/sim/Simulation.h"

namespace {

using namespace sluice;

using bench::Figures;
using bench::figures;

int usage(const char* why) {
    std::fprintf(stderr,
                 "collider_bench: %s\nusage: collider_bench SCENE DENSE.slc SPARSE.slc "
                 "[--steps N] [--repeat R]\n",
                 why);
    return 2;
}

/// The collider's samples as the SDF buffer holds them.
std::vector<std::byte> sdfBytes(const format::ColliderAsset& asset) {
    if (asset.sparse())
        return {asset.grid.begin(), asset.grid.end()};
    std::vector<std::byte> out(asset.distances.size() * sizeof(float));
    std::memcpy(out.data(), asset.distances.data(), out.size());
    return out;
}

// Reads DENSE and SPARSE (argv[2], argv[3]) into assets; 0, or usage()'s code.
int readAssets(char** argv, format::ColliderAsset (&assets)[2]) {
    for (int k = 0; k < 2; ++k) {
        auto read = format::readAsset(argv[2 + k]);
        if (!read)
            return usage(read.error().message().c_str());
        assets[k] = std::move(*read);
    }
    if (assets[0].sparse() || !assets[1].sparse())
        return usage("DENSE must be dense and SPARSE sparse");
    if (assets[0].meta.dims != assets[1].meta.dims ||
        assets[0].meta.origin != assets[1].meta.origin ||
        assets[0].meta.voxelSize != assets[1].meta.voxelSize)
        std::fprintf(stderr, "collider_bench: warning: the two grids differ; the lookups still "
                             "compare, the steps less so\n");
    return 0;
}

// Each asset's samples, record and texel view on the GPU, as the probe pass reads them.
struct ColliderGpu {
    gpu::Buffer sdf[2], records[2];
    gpu::BufferTexture texels[2]; // the dense grid's samples are fetched through it
};

int uploadColliders(const format::ColliderAsset (&assets)[2], ColliderGpu& g) {
    for (int k = 0; k < 2; ++k) {
        auto bytes = gpu::Buffer::createFrom(sdfBytes(assets[k]), "sdf");
        const shared::GpuCollider one = gpu::colliderRecord(assets[k], 0);
        auto record = gpu::colliderRecordBuffer(std::span(&one, 1));
        if (!bytes || !record)
            return usage("cannot allocate the collider buffers");
        auto view = gpu::BufferTexture::createR32F(*bytes, "sdf texels");
        if (!view)
            return usage(view.error().message().c_str());
        g.sdf[k] = std::move(*bytes);
        g.records[k] = std::move(*record);
        g.texels[k] = std::move(*view);
    }
    return 0;
}

// GPU time of one probe pass over the points with collider k bound [ms].
double timeLookups(const gpu::Program& probe, const ColliderGpu& g, int k,
                   const gpu::Buffer& pointBuf, const gpu::Buffer& out, std::size_t count) {
    const auto groups = std::uint32_t((count + shared::kPbfLocalSize - 1) / shared::kPbfLocalSize);
    gpu::GpuTimer timer;
    gpu::bindColliderRecords(g.records[k]);
    g.sdf[k].bindStorage(shared::kBindSdf);
    g.texels[k].bindTexture(shared::kUnitSdfTexels);
    pointBuf.bindStorage(shared::kBindPosIn);
    out.bindStorage(shared::kBindPosOut);
    probe.use();
    probe.set("uCount", std::uint32_t(count));
    timer.begin();
    probe.dispatchChunked(glm::uvec3(groups, 1, 1), 65535);
    timer.end();
    return double(timer.elapsedNs()) * 1e-6;
}

void report(const char* scene, std::size_t points, int steps, int repeat,
            const gpu::Context& context, const std::vector<double> (&lookupMs)[2],
            const std::vector<double> (&stepMs)[2]) {
    std::printf("collider_bench: %s, %zu points after %d steps, %d repeats (GPU time)\n", scene,
                points, steps, repeat);
    std::printf("renderer: %s\n", context.info().renderer.c_str());
    const char* names[2] = {"dense", "sparse"};
    Figures lookup[2], step[2];
    for (int k = 0; k < 2; ++k) {
        lookup[k] = figures(lookupMs[k]);
        step[k] = figures(stepMs[k]);
        std::printf("  %-6s  lookups %8.3f ms (%.3f-%.3f)   step %9.3f ms (%.3f-%.3f)\n", names[k],
                    lookup[k].median, lookup[k].lo, lookup[k].hi, step[k].median, step[k].lo,
                    step[k].hi);
    }
    std::printf("  sparse / dense: lookups %.2fx, whole step %.3fx\n",
                lookup[1].median / lookup[0].median, step[1].median / step[0].median);
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 4)
        return usage("SCENE, DENSE and SPARSE are required");
    int steps = 30, repeat = 15;
    for (int i = 4; i + 1 < argc; i += 2) {
        if (std::strcmp(argv[i], "--steps") == 0)
            steps = std::max(1, std::atoi(argv[i + 1]));
        else if (std::strcmp(argv[i], "--repeat") == 0)
            repeat = std::max(1, std::atoi(argv[i + 1]));
        else
            return usage("unknown option");
    }
    auto scene = format::readScene(argv[1]);
    if (!scene)
        return usage(scene.error().message().c_str());
    if (scene->colliders.size() != 1)
        return usage("the scene must have exactly one collider");
    format::ColliderAsset assets[2];
    if (int code = readAssets(argv, assets))
        return code;
    auto context = gpu::Context::createHeadless();
    if (!context)
        return usage(context.error().message().c_str());

    // The scene with one collider asset: the points, and a step to time.
    auto simulationWith = [&](int k) {
        return rt::Simulation::create(*scene, std::vector<format::ColliderAsset>{assets[k]});
    };
    auto warm = simulationWith(0);
    if (!warm)
        return usage(warm.error().message().c_str());
    for (int s = 0; s < steps; ++s)
        warm->step();
    const std::vector<rt::ParticleState> state = warm->downloadParticles();
    std::vector<glm::vec4> points;
    for (const rt::ParticleState& p : state)
        points.emplace_back(p.position, 0.0f); // w: collider 0 (the bits of 0u)

    const std::array<gpu::ShaderDefine, 1> sparseDefine{{{"SLUICE_SPARSE_COLLIDERS", "1"}}};
    auto probe = gpu::Program::compute(
        "collider_probe.comp", rt::shaders::shaderSource("collider_probe.comp"), sparseDefine);
    if (!probe)
        return usage(probe.error().message().c_str());
    auto pointBuf = gpu::Buffer::createFrom(points, "points");
    auto out = gpu::Buffer::create(points.size() * sizeof(glm::vec4), "samples");
    if (!pointBuf || !out)
        return usage("cannot allocate the point buffers");
    ColliderGpu colliders;
    if (int code = uploadColliders(assets, colliders))
        return code;
    auto sims = std::array{simulationWith(0), simulationWith(1)};
    for (int k = 0; k < 2; ++k) {
        if (!sims[k])
            return usage(sims[k].error().message().c_str());
        if (auto ok = sims[k]->setParticles(state); !ok)
            return usage(ok.error().message().c_str());
        sims[k]->step(); // warm up: programs, buffers
    }

    std::vector<double> lookupMs[2], stepMs[2];
    for (int r = 0; r < repeat; ++r)
        for (int k = 0; k < 2; ++k) {
            lookupMs[k].push_back(
                timeLookups(*probe, colliders, k, *pointBuf, *out, points.size()));
            if (auto ok = sims[k]->setParticles(state); !ok)
                return usage(ok.error().message().c_str());
            gpu::GpuTimer stepTimer;
            stepTimer.begin();
            sims[k]->step();
            stepTimer.end();
            stepMs[k].push_back(double(stepTimer.elapsedNs()) * 1e-6);
        }
    report(argv[1], points.size(), steps, repeat, *context, lookupMs, stepMs);
    return 0;
}
