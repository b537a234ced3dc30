// Bindings, work-group size, parameters and reference formula of gpu_selftest.comp.
// Shared by GLSL and C++ (Context::selfTest computes the same formula on the CPU).
#ifndef SLUICE_SHARED_GPU_SELF_TEST_H
#define SLUICE_SHARED_GPU_SELF_TEST_H

#include "shared/GlslBridge.h"

SLUICE_SHARED_BEGIN

/// Local work-group size of gpu_selftest.comp [invocations].
SLUICE_CONST int kSelfTestLocalSize = 64;
/// SSBO binding of the SelfTestParams block.
SLUICE_CONST int kSelfTestParamsBinding = 0;
/// SSBO binding of the float output array, one value per invocation.
SLUICE_CONST int kSelfTestOutputBinding = 1;

/// Parameters of the self-test kernel, std430 (32 bytes).
struct SelfTestParams {
    uint count;      ///< number of output values
    float amplitude; ///< of the sine term
    float frequency; ///< [rad per index] of the sine term, applied to i % 1024
    float slope;     ///< weight of the (i % 7) term
    vec4 bias;       ///< bias.x is added to every value; yzw unused
};

/// The value the kernel writes at index i. Arguments of sin stay below 1024 * frequency, so
/// GPU and CPU sines agree to about 1e-6 for frequency <= 2 pi / 1024.
SLUICE_FUNC float selfTestValue(uint i, SelfTestParams p) {
    return p.amplitude * sin(p.frequency * float(i % 1024u)) + p.slope * float(i % 7u) + p.bias.x;
}

SLUICE_SHARED_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(sluice::shared::SelfTestParams) == 32, "std430 size of SelfTestParams");
static_assert(offsetof(sluice::shared::SelfTestParams, slope) == 12, "std430 offset of slope");
static_assert(offsetof(sluice::shared::SelfTestParams, bias) == 16, "std430 offset of bias (vec4)");
#endif

#endif // SLUICE_SHARED_GPU_SELF_TEST_H
