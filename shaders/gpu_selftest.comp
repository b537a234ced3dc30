// Self-test kernel: writes selfTestValue(i) for every index, proving embed -> include -> compile
// -> dispatch (plain or chunked) -> readback. The CPU computes the same shared formula.
#version 450 core

#include "shared/GpuSelfTest.h"
#include "shared/ChunkedDispatch.h"

layout(local_size_x = kSelfTestLocalSize) in;

layout(std430, binding = kSelfTestParamsBinding) readonly buffer Params {
    SelfTestParams params;
};

layout(std430, binding = kSelfTestOutputBinding) writeonly buffer Output {
    float values[];
};

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= params.count)
        return;
    values[i] = selfTestValue(i, params);
}
