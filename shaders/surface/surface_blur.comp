// One axis of the Gaussian field's blur: every stored sample becomes the weighted sum of the
// samples within SLUICE_BLUR_RADIUS along axis SLUICE_BLUR_AXIS (weights uWeights, summing to
// 1 over the taps). One work group per stored block, one invocation per line of
// kSurfaceBlockSide samples along the axis, which reads its line and the radius each way once.
// A sample in a block that is not stored reads as 0 (no particle reaches it). Run along x, y
// and z: the deposit (fixed point) becomes the field (fixed point), floats between. The axis
// and radius are compiled in (SurfaceReconstructor.cpp builds one program per axis and radius),
// so the loops unroll and the line stays in registers.
#version 450 core

#include "glsl/SurfaceGlsl.h"

#ifndef SLUICE_BLUR_AXIS
#define SLUICE_BLUR_AXIS 0
#endif
#ifndef SLUICE_BLUR_RADIUS
#define SLUICE_BLUR_RADIUS 4
#endif

layout(local_size_x = kSurfaceBlockRows) in;

layout(std430, binding = kSurfBindBlurIn) readonly buffer BlurIn { uint blurIn[]; };
layout(std430, binding = kSurfBindBlurOut) writeonly buffer BlurOut { uint blurOut[]; };

const int kAxis = SLUICE_BLUR_AXIS;      // 0, 1, 2: x, y, z; x reads the deposit, z writes
const int kRadius = SLUICE_BLUR_RADIUS;  // taps -kRadius .. kRadius
const int kSide = int(kSurfaceBlockSide);
const int kLine = kSide + 2 * kRadius;

uniform float uWeights[kRadius + 1]; // taps k and -k
uniform float uOutScale;             // the field's fixed point per unit of the last pass

float readIn(uint index) {
    uint v = blurIn[index];
    return kAxis == 0 ? float(v) * (1.0 / kSurfaceDepositScale) : uintBitsToFloat(v);
}

void main() {
    uint slot = SLUICE_GLOBAL_ID.x / kSurfaceBlockRows;
    uint lane = gl_LocalInvocationID.x;
    if (slot >= uCount)
        return;
    ivec3 b = blockCoord(activeBlock[slot]);
    // The line's fixed coordinates: the two other axes, the lower one fastest across the lanes
    // (neighbouring lanes read neighbouring samples along y and z).
    int a = int(lane % kSurfaceBlockSide);
    int c = int(lane / kSurfaceBlockSide);
    ivec3 local = kAxis == 0 ? ivec3(0, a, c) : (kAxis == 1 ? ivec3(a, 0, c) : ivec3(a, c, 0));
    ivec3 along = ivec3(kAxis == 0 ? 1 : 0, kAxis == 1 ? 1 : 0, kAxis == 2 ? 1 : 0);
    const uint stride = kAxis == 0 ? 1u : (kAxis == 1 ? kSurfaceBlockSide : kSurfaceBlockRows);
    uint below = storedBlockBase(b - along);
    uint here = storedBlockBase(b);
    uint above = storedBlockBase(b + along);
    uint start = laneOf(local);
    float line[kLine];
    for (int t = 0; t < kLine; ++t) {
        int at = t - kRadius;
        int step = at < 0 ? -1 : (at >= kSide ? 1 : 0);
        uint base = step < 0 ? below : (step > 0 ? above : here);
        line[t] = base != 0xffffffffu ? readIn(base + start + uint(at - kSide * step) * stride)
                                      : 0.0;
    }
    for (int t = 0; t < kSide; ++t) {
        float sum = uWeights[0] * line[t + kRadius];
        for (int k = 1; k <= kRadius; ++k)
            sum += uWeights[k] * (line[t + kRadius - k] + line[t + kRadius + k]);
        uint index = here + start + uint(t) * stride;
        blurOut[index] = kAxis == 2 ? uint(sum * uOutScale + 0.5) : floatBitsToUint(sum);
    }
}
