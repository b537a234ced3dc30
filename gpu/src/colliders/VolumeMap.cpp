// computeVolumeMap: one collider's volume map on the GPU, through the solver's own pass, with
// buffers of its own: the grid, then the map, in one SDF buffer.
#include "sluice/gpu/colliders/VolumeMap.h"

#include <cmath>
#include <string>

#include "shared/Pbf.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/GridSamples.h"
#include "sluice/format/asset/Half.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/colliders/ColliderRecord.h"
#include "sluice/gpu/colliders/SparseGrids.h"
#include "sluice/gpu/colliders/VolumeMapPass.h"

namespace sluice::gpu {
namespace {

// The support a map can be computed for: more than a hundredth of a voxel (the quadrature's
// cells stay normal floats) and at most the grid's diagonal (a larger ball reads only
// extrapolated field).
Result<void> checkSupport(const format::ColliderAsset& asset, double support) {
    const format::ColliderMeta& m = asset.meta;
    const double diagonal = glm::length(glm::dvec3(m.dims - glm::uvec3(1))) * m.voxelSize;
    if (!std::isfinite(support) || !(support >= 0.01 * m.voxelSize) || support > diagonal)
        return fail(ErrorCode::InvalidArgument,
                    "volume map support " + std::to_string(support) +
                        " is not a number between a hundredth of a voxel (" +
                        std::to_string(0.01 * m.voxelSize) + ") and the grid's diagonal (" +
                        std::to_string(diagonal) + ")");
    return {};
}

// The field as the file stores it: an f16 asset's samples rounded to half, as a reader gets them.
std::vector<float> storedSamples(const format::ColliderAsset& asset) {
    std::vector<float> out = asset.distances;
    if (asset.meta.storage == format::Storage::F16)
        for (float& v : out)
            v = format::halfToFloat(format::floatToHalf(v));
    return out;
}

} // namespace

Result<std::vector<float>> computeVolumeMap(const format::ColliderAsset& asset, double support) {
    if (auto ok = checkSupport(asset, support); !ok)
        return ok.error();
    const std::uint64_t points = format::volumeMapPoints(asset);
    if (points > format::kMaxVolumeMapPoints)
        return fail(ErrorCode::SizeOverflow,
                    "a volume map of " + std::to_string(points) + " points exceeds the limit of " +
                        std::to_string(format::kMaxVolumeMapPoints) + "; coarsen the bake");
    // The grid as the solver packs it, then the map.
    const std::uint64_t gridBytes =
        asset.sparse() ? sparseSlotBytes(asset) : asset.pointCount() * sizeof(float);
    const std::uint64_t bytes = gridBytes + points * sizeof(float);
    GLint64 maxBlock = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    if (maxBlock > 0 && bytes > std::uint64_t(maxBlock))
        return fail(ErrorCode::GpuOutOfMemory,
                    "the grid and its volume map need " + std::to_string(bytes) +
                        " bytes, more than this GL allows in one storage block (" +
                        std::to_string(maxBlock) + "); coarsen the bake");
    auto sdf = Buffer::create(bytes, "volume map bake");
    if (!sdf)
        return sdf.error();
    if (asset.sparse())
        sdf->upload(asset.grid.data(), asset.grid.size());
    else
        sdf->upload(storedSamples(asset));
    shared::GpuCollider record = colliderRecord(asset, 0);
    record.volumeMap = std::uint32_t(gridBytes / sizeof(float));
    auto records = colliderRecordBuffer(std::span(&record, 1));
    if (!records)
        return records.error();
    // The pass reads no parameter, but its parameter block is declared: backed by zeros.
    auto params = Buffer::create(sizeof(shared::PbfParams), "volume map bake params");
    if (!params)
        return params.error();
    const std::uint32_t zero = 0;
    glClearNamedBufferData(params->id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    std::vector<ShaderDefine> defines = {{"SLUICE_SDF_STORAGE", "1"}};
    if (asset.sparse())
        defines.push_back({"SLUICE_SPARSE_COLLIDERS", "1"});
    auto pass = volumeMapProgram(defines);
    if (!pass)
        return pass.error();
    params->bindBase(GL_UNIFORM_BUFFER, shared::kBindParams);
    bindColliderRecords(*records);
    sdf->bindStorage(shared::kBindSdf);
    sdf->bindStorage(shared::kBindVolumeMapOut);
    dispatchVolumeMap(*pass, 0, asset, support);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    return sdf->download<float>(std::size_t(record.volumeMap), std::size_t(points));
}

} // namespace sluice::gpu
