// Anisotropic kernels, step 2: writes each particle's index and position into its block's run
// (binStart, scanned from the counts), counting binCount back down to 0; the neighbour loop
// then reads positions in runs, not through the indices. The order within a run depends
// on the atomics; nothing after depends on it (surface_anisotropy.comp sums in fixed point).
#version 450 core

#include "glsl/SurfaceKernelGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

layout(std430, binding = kSurfBindBinCount) buffer BinCount { uint binCount[]; };
layout(std430, binding = kSurfBindBinStart) readonly buffer BinStart { uint binStart[]; };
layout(std430, binding = kSurfBindBinParticles) writeonly buffer BinParticles {
    uint binParticles[];
};
layout(std430, binding = kSurfBindBinPoints) writeonly buffer BinPoints { vec4 binPoints[]; };

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= uCount)
        return;
    uint b = blockIndex(blockOfPoint(points[i].xyz));
    uint slot = binStart[b] + atomicAdd(binCount[b], 0xffffffffu) - 1u;
    binParticles[slot] = i;
    binPoints[slot] = points[i];
}
