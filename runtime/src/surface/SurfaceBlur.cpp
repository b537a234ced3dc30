// The Gaussian field's blur passes (SurfaceBlur.h).
#include "surface/SurfaceBlur.h"

#include <span>
#include <string>
#include <utility>

#include "shared/Surface.h"
#include "sluice/rt/RuntimeShaders.h"
#include "surface/SurfaceGpu.h"

namespace sluice::rt {

namespace sh = shared;

Result<void> GaussianBlurPasses::prepare(int radius) {
    if (m_programs.contains(radius))
        return {};
    std::array<gpu::Program, 3> made;
    for (int axis = 0; axis < 3; ++axis) {
        const gpu::ShaderDefine defines[] = {{"SLUICE_BLUR_AXIS", std::to_string(axis)},
                                             {"SLUICE_BLUR_RADIUS", std::to_string(radius)}};
        auto program = gpu::Program::compute("surface_blur.comp",
                                             shaders::shaderSource("surface_blur.comp"), defines);
        if (!program)
            return program.error();
        made[std::size_t(axis)] = std::move(*program);
    }
    m_programs.emplace(radius, std::move(made));
    return {};
}

Result<void> GaussianBlurPasses::run(const SurfaceBlur& b, const SurfaceGrid& g,
                                     const SurfaceOptions& o, const gpu::Buffer& field,
                                     std::uint32_t activeBlocks) {
    if (auto ok = prepare(b.radius); !ok)
        return ok;
    const std::uint64_t samples = std::uint64_t(activeBlocks) * sh::kSurfaceBlockSamples;
    for (gpu::Buffer& buffer : m_blurred)
        if (auto ok = surface::ensureUints(buffer, samples, "surface blur", false); !ok)
            return ok;
    const float c = o.cellSize;
    const float volume = particleVolume(o);
    const gpu::Buffer* from[3] = {&field, &m_blurred[0], &m_blurred[1]};
    const gpu::Buffer* to[3] = {&m_blurred[0], &m_blurred[1], &field};
    const std::array<gpu::Program, 3>& programs = m_programs.at(b.radius);
    for (std::size_t axis = 0; axis < 3; ++axis) {
        const gpu::Program& p = programs[axis];
        setGridUniforms(p, g, o);
        p.set("uCount", activeBlocks);
        p.set("uWeights", std::span<const float>(b.weights.data(), std::size_t(b.radius) + 1));
        p.set("uOutScale", volume / (c * c * c) * sh::kSurfaceFixedScale);
        from[axis]->bindStorage(sh::kSurfBindBlurIn);
        to[axis]->bindStorage(sh::kSurfBindBlurOut);
        p.dispatchChunked(glm::uvec3(activeBlocks, 1, 1), surface::kMaxGroupsPerDispatch);
        surface::barrier();
    }
    return {};
}

} // namespace sluice::rt
