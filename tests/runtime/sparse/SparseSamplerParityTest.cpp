// The solver's GLSL collider sampler (sampleCollider in glsl/PbfGlsl.h, NanoVDB's PNanoVDB.h
// for sparse grids) against the CPU sampler of the same field (format::SdfSampler), on 10^5+
// points: in the band, near the surface, deep inside, outside the band and outside the box.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "GpuTest.h"
#include "asset/SparseTestUtil.h"
#include "shared/Pbf.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/BufferTexture.h"
#include "sluice/gpu/Program.h"
#include "sluice/gpu/colliders/ColliderRecord.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice {
namespace {

using gpu::test::GpuTest;

/// A dense asset holding the sparse asset's values at every grid point (tiles included), so
/// both layouts describe exactly the same trilinear field.
format::ColliderAsset densified(const format::ColliderAsset& sparse) {
    const auto& tree = test::nanoGrid(sparse).tree();
    format::ColliderAsset dense;
    dense.meta = sparse.meta;
    dense.meta.layout = format::Layout::Dense;
    dense.meta.bandWidth = 0.0;
    dense.distances.resize(dense.pointCount());
    for (std::uint32_t k = 0; k < dense.meta.dims.z; ++k)
        for (std::uint32_t j = 0; j < dense.meta.dims.y; ++j)
            for (std::uint32_t i = 0; i < dense.meta.dims.x; ++i)
                dense.distances[dense.index(i, j, k)] = tree.getValue(
                    nanovdb::Coord(std::int32_t(i), std::int32_t(j), std::int32_t(k)));
    return dense;
}

class SparseSamplerParity : public GpuTest {
protected:
    // Uploads the assets as Simulation does, into one SDF buffer: dense grids as float words
    // first, then sparse grids at 32-byte aligned offsets after `sparsePad` more bytes (so
    // offsets other than the first are exercised). Then samples collider `points[i].w` at each
    // point on the GPU, the dense grids fetched through the buffer's texel view as the solver
    // does, or with `fromStorage` read from the storage block (SLUICE_SDF_STORAGE).
    std::vector<glm::vec4> sample(const std::vector<const format::ColliderAsset*>& assets,
                                  const std::vector<glm::vec4>& points, std::size_t sparsePad,
                                  bool fromStorage = false) {
        std::vector<shared::GpuCollider> records;
        std::vector<std::byte> data;
        for (const format::ColliderAsset* a : assets)
            if (!a->sparse()) {
                const auto* bytes = reinterpret_cast<const std::byte*>(a->distances.data());
                data.insert(data.end(), bytes, bytes + a->distances.size() * sizeof(float));
            }
        data.resize(((data.size() + 31) & ~std::size_t(31)) + sparsePad);
        std::size_t denseWords = 0;
        for (const format::ColliderAsset* a : assets) {
            if (a->sparse()) {
                records.push_back(gpu::colliderRecord(*a, std::uint32_t(data.size())));
                data.insert(data.end(), a->grid.begin(), a->grid.end());
                data.resize((data.size() + 31) & ~std::size_t(31));
            } else {
                records.push_back(gpu::colliderRecord(*a, std::uint32_t(denseWords)));
                denseWords += a->distances.size();
            }
        }
        data.resize(std::max<std::size_t>(data.size(), 4));
        auto colliderBuf = gpu::colliderRecordBuffer(records);
        auto sdfBuf = gpu::Buffer::createFrom(data, "sdf");
        auto pointBuf = gpu::Buffer::createFrom(points, "points");
        auto out = gpu::Buffer::create(points.size() * sizeof(glm::vec4), "samples");
        EXPECT_TRUE(colliderBuf && sdfBuf && pointBuf && out);
        if (!colliderBuf || !sdfBuf || !pointBuf || !out)
            return {};
        auto texels = gpu::BufferTexture::createR32F(*sdfBuf, "sdf texels");
        EXPECT_TRUE(texels) << texels.error().message();
        std::vector<gpu::ShaderDefine> defines{{"SLUICE_SPARSE_COLLIDERS", "1"}};
        if (fromStorage)
            defines.push_back({"SLUICE_SDF_STORAGE", "1"});
        auto program = gpu::Program::compute(
            "collider_probe.comp", rt::shaders::shaderSource("collider_probe.comp"), defines);
        EXPECT_TRUE(program) << program.error().message();
        if (!program || !texels)
            return {};
        gpu::bindColliderRecords(*colliderBuf);
        sdfBuf->bindStorage(shared::kBindSdf);
        texels->bindTexture(shared::kUnitSdfTexels);
        pointBuf->bindStorage(shared::kBindPosIn);
        out->bindStorage(shared::kBindPosOut);
        program->use();
        program->set("uCount", std::uint32_t(points.size()));
        const auto groups =
            std::uint32_t((points.size() + shared::kPbfLocalSize - 1) / shared::kPbfLocalSize);
        program->dispatchChunked(glm::uvec3(groups, 1, 1), 1024);
        return out->download<glm::vec4>();
    }
};

/// Points for collider `index` of `asset`: stratified over the grid box and a margin around it,
/// half of them within two band widths of the sphere's surface (centre c, radius r).
std::vector<glm::vec4> probePoints(const format::ColliderAsset& asset, std::uint32_t index,
                                   glm::dvec3 c, double r, std::size_t count) {
    std::mt19937 rng(1234 + index);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double voxel = asset.meta.voxelSize;
    const glm::dvec3 lo = asset.meta.origin - 2.0 * voxel;
    const glm::dvec3 size = glm::dvec3(asset.meta.dims - glm::uvec3(1)) * voxel + 4.0 * voxel;
    const double band = asset.meta.bandWidth * voxel;
    float bits;
    std::memcpy(&bits, &index, sizeof bits);
    std::vector<glm::vec4> points;
    points.reserve(count);
    for (std::size_t n = 0; n < count; ++n) {
        glm::dvec3 p;
        if (n % 2 == 0) {
            p = lo + glm::dvec3(unit(rng), unit(rng), unit(rng)) * size;
        } else {
            glm::dvec3 dir(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
            dir = glm::length(dir) > 1e-6 ? glm::normalize(dir) : glm::dvec3(1, 0, 0);
            p = c + dir * (r + (2.0 * unit(rng) - 1.0) * 2.0 * band);
        }
        points.emplace_back(glm::vec3(p), bits);
    }
    return points;
}

TEST_F(SparseSamplerParity, GlslMatchesTheCpuSamplerInTheBandAndKeepsTheSignOutsideIt) {
    const glm::dvec3 centre{0.1, -0.2, 0.3};
    const double radius = 0.5, voxel = 0.05, band = 3.0;
    const format::ColliderAsset sphere = test::makeSparseSphere(radius, voxel, band, centre);
    const format::SdfSampler cpu(sphere);
    const std::vector<glm::vec4> points = probePoints(sphere, 0, centre, radius, 120000);
    const std::vector<glm::vec4> gpu = sample({&sphere}, points, 64);
    ASSERT_EQ(gpu.size(), points.size());

    std::size_t inBand = 0, deepInside = 0, outsideBand = 0, signErrors = 0, worst = 0;
    double maxBandError = 0.0, maxGradError = 0.0;
    for (std::size_t n = 0; n < points.size(); ++n) {
        const glm::dvec3 p(glm::vec3(points[n]));
        const double want = cpu.value(p);
        const double got = gpu[n].w;
        ASSERT_TRUE(std::isfinite(got)) << "point " << n;
        if (std::abs(want) < 0.999 * band * voxel && cpu.contains(p)) {
            ++inBand;
            const double error = std::abs(got - want) / voxel;
            if (error > maxBandError) {
                maxBandError = error;
                worst = n;
            }
            maxGradError = std::max(maxGradError,
                                    glm::length(glm::dvec3(glm::vec3(gpu[n])) - cpu.gradient(p)));
        } else {
            ++outsideBand;
            deepInside += want < 0.0 ? 1 : 0;
            signErrors += (want < 0.0) != (got < 0.0) ? 1 : 0;
        }
    }
    // Both kinds of points are there in numbers: the test samples what it claims to.
    EXPECT_GT(inBand, 30000u);
    EXPECT_GT(outsideBand, 30000u);
    EXPECT_GT(deepInside, 1000u);
    EXPECT_LE(maxBandError, 1e-5) << "at " << points[worst].x << ", " << points[worst].y << ", "
                                  << points[worst].z;
    EXPECT_LE(maxGradError, 1e-4); // |grad| is about 1: float rounding of the differences
    EXPECT_EQ(signErrors, 0u);
}

TEST_F(SparseSamplerParity, DenseAndSparseCollidersInOneBufferSampleTheSameField) {
    // Two sparse spheres and the dense copy of the first, mixed in one record array: each
    // record reads its own grid (sparse offsets after the first are not 0).
    const format::ColliderAsset a = test::makeSparseSphere(0.5, 0.05, 3.0, {0.1, -0.2, 0.3});
    const format::ColliderAsset b = test::makeSparseSphere(0.3, 0.04, 4.0, {-1.0, 0.5, 0.0});
    const format::ColliderAsset aDense = densified(a);
    std::vector<glm::vec4> points = probePoints(a, 0, {0.1, -0.2, 0.3}, 0.5, 20000);
    const std::vector<glm::vec4> pointsB = probePoints(b, 1, {-1.0, 0.5, 0.0}, 0.3, 20000);
    std::vector<glm::vec4> pointsDense = probePoints(aDense, 2, {0.1, -0.2, 0.3}, 0.5, 20000);
    points.insert(points.end(), pointsB.begin(), pointsB.end());
    points.insert(points.end(), pointsDense.begin(), pointsDense.end());
    const std::vector<glm::vec4> gpu = sample({&a, &b, &aDense}, points, 0);
    ASSERT_EQ(gpu.size(), points.size());
    const format::SdfSampler cpuA(a), cpuB(b), cpuDense(aDense);
    const format::SdfSampler* cpu[3] = {&cpuA, &cpuB, &cpuDense};
    const double voxel[3] = {0.05, 0.04, 0.05};
    double maxError[3] = {0.0, 0.0, 0.0};
    for (std::size_t n = 0; n < points.size(); ++n) {
        const std::size_t c = n / 20000;
        const glm::dvec3 p(glm::vec3(points[n]));
        maxError[c] = std::max(maxError[c], std::abs(gpu[n].w - cpu[c]->value(p)) / voxel[c]);
    }
    for (int c = 0; c < 3; ++c)
        EXPECT_LE(maxError[c], 1e-5) << "collider " << c;
    // The dense copy and the sparse original agree point for point.
    double layoutDifference = 0.0;
    for (std::size_t n = 0; n < 20000; ++n)
        layoutDifference = std::max(
            layoutDifference,
            double(std::abs(gpu[n].w - float(cpuDense.value(glm::dvec3(glm::vec3(points[n])))))));
    EXPECT_LE(layoutDifference / 0.05, 1e-5);
}

// The passes fetch dense samples through the SDF buffer's texel view, or read the storage block
// where the buffer holds more texels than the GL allows: the same bits either way.
TEST_F(SparseSamplerParity, TheTexelViewAndTheStorageBlockGiveTheSameBits) {
    const format::ColliderAsset sparse = test::makeSparseSphere(0.5, 0.05, 3.0, {0.1, -0.2, 0.3});
    const format::ColliderAsset dense = densified(sparse);
    // Two dense copies, so the second's samples start past the first's (an offset other than 0).
    std::vector<glm::vec4> points = probePoints(dense, 0, {0.1, -0.2, 0.3}, 0.5, 20000);
    const std::vector<glm::vec4> second = probePoints(dense, 1, {0.1, -0.2, 0.3}, 0.5, 20000);
    points.insert(points.end(), second.begin(), second.end());
    const std::vector<glm::vec4> texels = sample({&dense, &dense}, points, 0, false);
    const std::vector<glm::vec4> storage = sample({&dense, &dense}, points, 0, true);
    ASSERT_EQ(texels.size(), points.size());
    ASSERT_EQ(storage.size(), points.size());
    std::size_t differing = 0;
    for (std::size_t n = 0; n < points.size(); ++n)
        differing += std::memcmp(&texels[n], &storage[n], sizeof(glm::vec4)) != 0 ? 1 : 0;
    EXPECT_EQ(differing, 0u);
    // Not vacuous: the field varies over the points, and the view really fetched it.
    const format::SdfSampler cpu(dense);
    double maxError = 0.0;
    for (std::size_t n = 0; n < points.size(); ++n)
        maxError = std::max(
            maxError, std::abs(double(texels[n].w) - cpu.value(glm::dvec3(glm::vec3(points[n])))));
    EXPECT_LE(maxError / 0.05, 1e-5);
}

} // namespace
} // namespace sluice
