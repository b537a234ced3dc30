// Anisotropic kernels, step 1: counts the particles in each block of the grid (binCount), so a
// prefix scan can give every block a contiguous run of particle indices.
#version 450 core

#include "glsl/SurfaceKernelGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

layout(std430, binding = kSurfBindBinCount) buffer BinCount { uint binCount[]; };

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uCount)
        return;
    atomicAdd(binCount[blockIndex(blockOfPoint(points[i].xyz))], 1u);
}
