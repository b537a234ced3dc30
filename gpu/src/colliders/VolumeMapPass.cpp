// The volume map pass's program and dispatch, as the solver and the bake run it.
#include "sluice/gpu/colliders/VolumeMapPass.h"

#include "shared/Pbf.h"
#include "sluice/format/asset/GridSamples.h"
#include "sluice/gpu/ColliderShaders.h"

namespace sluice::gpu {

Result<Program> volumeMapProgram(const std::vector<ShaderDefine>& defines) {
    return Program::compute("pbf_volume_map.comp",
                            collider_shaders::shaderSource("pbf_volume_map.comp"), defines);
}

void dispatchVolumeMap(const Program& pass, std::uint32_t collider,
                       const format::ColliderAsset& asset, double support) {
    pass.set("uCollider", collider);
    pass.set("uSupport", float(support));
    pass.set("uStride", volumeMapStride(support, asset.meta.voxelSize));
    const auto points = std::uint32_t(format::volumeMapPoints(asset));
    pass.set("uPoints", points);
    const std::uint32_t groups = (points + shared::kPbfLocalSize - 1) / shared::kPbfLocalSize;
    pass.dispatchChunked(glm::uvec3(groups, 1, 1), shared::kPbfMaxGroupsPerDispatch);
}

} // namespace sluice::gpu
