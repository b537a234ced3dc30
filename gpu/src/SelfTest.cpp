// Context::selfTest: the embedded gpu_selftest.comp against the same formula on the CPU.
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "shared/GpuSelfTest.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Context.h"
#include "sluice/gpu/GpuShaders.h"
#include "sluice/gpu/Program.h"

namespace sluice::gpu {

Result<void> Context::selfTest(std::uint32_t count, std::uint32_t maxGroupsPerDispatch) const {
    SLUICE_ASSERT(count > 0, "Context::selfTest needs at least one value");
    makeCurrent();
    auto program =
        Program::compute("gpu_selftest.comp", shaders::shaderSource("gpu_selftest.comp"));
    if (!program)
        return program.error();

    const std::array<shared::SelfTestParams, 1> params{shared::SelfTestParams{
        count, 0.75f, 2.0f * std::numbers::pi_v<float> / 1024.0f, 0.125f, {0.5f, 0, 0, 0}}};
    auto paramsBuffer = Buffer::createFrom(params, "selftest params");
    if (!paramsBuffer)
        return paramsBuffer.error();
    auto output = Buffer::create(std::size_t{count} * sizeof(float), "selftest output");
    if (!output)
        return output.error();
    paramsBuffer->bindStorage(shared::kSelfTestParamsBinding);
    output->bindStorage(shared::kSelfTestOutputBinding);

    const glm::uvec3 groups(groupCount(count, shared::kSelfTestLocalSize), 1, 1);
    if (maxGroupsPerDispatch > 0)
        program->dispatchChunked(groups, maxGroupsPerDispatch);
    else
        program->dispatch(groups);
    const std::vector<float> values = output->download<float>();

    // Values lie in [-0.75, 2]; an index off by one moves a value by >= 0.004.
    constexpr float kTolerance = 1e-4f;
    std::uint32_t wrong = 0;
    std::uint32_t firstWrong = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
        const float expected = shared::selfTestValue(i, params[0]);
        if (!(std::abs(values[i] - expected) <= kTolerance) && wrong++ == 0)
            firstWrong = i;
    }
    if (wrong > 0)
        return fail(ErrorCode::NoGlContext,
                    "GPU self-test failed on " + m_info.renderer + ": " + std::to_string(wrong) +
                        " of " + std::to_string(count) + " values wrong, first at index " +
                        std::to_string(firstWrong) + " (" + std::to_string(values[firstWrong]) +
                        ", expected " +
                        std::to_string(shared::selfTestValue(firstWrong, params[0])) + ")");
    return {};
}

} // namespace sluice::gpu
