// The screen-space fluid's small spheres from render_splat.comp into the fluid's targets:
//   default            the nearest hit's view depth [m] (0 where none) and its window depth
//   SLUICE_THICKNESS   the summed thickness [m], fixed point to float, every pixel
// The larger spheres are drawn over it afterwards by the impostors from the list.
#version 450 core

#include "glsl/RenderGlsl.h"

layout(location = 0) out float outValue;

#ifdef SLUICE_THICKNESS
layout(binding = kRenderUnitSplatThickness) uniform usampler2D summed;

void main() {
    outValue = float(texelFetch(summed, ivec2(gl_FragCoord.xy), 0).r) / kSplatThicknessScale;
}
#else
layout(binding = kRenderUnitSplatDepth) uniform usampler2D nearest;

void main() {
    uint bits = texelFetch(nearest, ivec2(gl_FragCoord.xy), 0).r;
    if (bits == 0xffffffffu)
        discard;
    float depth = uintBitsToFloat(bits);
    gl_FragDepth = depth;
    outValue = -viewOfWindow(gl_FragCoord.xy * F.invViewportSize, depth).z;
}
#endif
