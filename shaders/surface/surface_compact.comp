// The list of stored blocks: activeBlock[slot] = the block's index, in block order.
#version 450 core

#include "glsl/SurfaceGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

void main() {
    uint b = SLUICE_GLOBAL_ID.x;
    if (b >= uCount)
        return;
    if (blockFlag[b] != 0u)
        activeBlock[blockSlot[b]] = b;
}
