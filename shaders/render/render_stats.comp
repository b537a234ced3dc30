// Viewer statistics without a stall: mean and max density error C_i and max speed over every
// particle, reduced per work group in shared memory and accumulated with atomics into a small
// buffer that the CPU copies and reads back a few frames later.
#version 450 core

#include "shared/Render.h"

layout(local_size_x = kRenderStatsLocalSize) in;

layout(std430, binding = kRenderBindVelocities) readonly buffer Velocities { vec4 vel[]; };
layout(std430, binding = kRenderBindStats) buffer Stats { RenderStats stats; };

uniform uint uCount;

shared uint sErrorSum[kRenderStatsLocalSize];
shared float sErrorMax[kRenderStatsLocalSize];
shared float sSpeedMax[kRenderStatsLocalSize];

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint l = gl_LocalInvocationID.x;
    float c = 0.0;
    float speed = 0.0;
    if (i < uCount) {
        // Clamped so one group's fixed-point sum always fits in 32 bits.
        c = clamp(vel[i].w, 0.0, 100.0);
        speed = length(vel[i].xyz);
    }
    sErrorSum[l] = uint(c * kRenderStatsFixedScale + 0.5);
    sErrorMax[l] = c;
    sSpeedMax[l] = speed;
    barrier();
    for (uint width = kRenderStatsLocalSize / 2u; width > 0u; width /= 2u) {
        if (l < width) {
            sErrorSum[l] += sErrorSum[l + width];
            sErrorMax[l] = max(sErrorMax[l], sErrorMax[l + width]);
            sSpeedMax[l] = max(sSpeedMax[l], sSpeedMax[l + width]);
        }
        barrier();
    }
    if (l == 0u) {
        uint old = atomicAdd(stats.errorLo, sErrorSum[0]);
        if (old + sErrorSum[0] < old)
            atomicAdd(stats.errorHi, 1u);
        atomicMax(stats.errorMaxBits, floatBitsToUint(sErrorMax[0]));
        atomicMax(stats.speedMaxBits, floatBitsToUint(sSpeedMax[0]));
    }
}
