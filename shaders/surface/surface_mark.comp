// Marks every block of the sample grid that a particle's kernel reaches (plus two cells, so a
// crossing edge always starts in a stored block): blockFlag = 1. Same value from any order.
#version 450 core

#include "glsl/SurfaceKernelGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uCount)
        return;
    SurfaceKernel k = kernelOf(i);
    vec3 p = (k.centre - uOrigin) / uCell;
    vec3 reach = k.extent / uCell + 2.0;
    ivec3 lo = clamp(ivec3(floor(p - reach)), ivec3(0), uSamples - 1) / int(kSurfaceBlockSide);
    ivec3 hi = clamp(ivec3(ceil(p + reach)), ivec3(0), uSamples - 1) / int(kSurfaceBlockSide);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x)
                blockFlag[blockIndex(ivec3(x, y, z))] = 1u;
}
