// The small spheres of render_splat.comp, shaded: each pixel's winning particle (nearest hit,
// lowest index among equal depths) is hit again along the pixel centre's ray and coloured as
// render_particles.frag colours it, with the depth the compute passes compared, so what is drawn
// after (the larger spheres, the glass walls) is tested against it.
#version 450 core

#include "glsl/RenderGlsl.h"

layout(std430, binding = kRenderBindPositions) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = kRenderBindVelocities) readonly buffer Velocities { vec4 velocities[]; };
layout(binding = kRenderUnitSplatDepth) uniform usampler2D nearest;
layout(binding = kRenderUnitSplatWinner) uniform usampler2D winner;

layout(location = 0) out vec4 outColour;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    uint i = texelFetch(winner, p, 0).r;
    if (i == 0xffffffffu)
        discard;
    float r = F.particleRadius;
    vec3 centre = (F.view * vec4(positions[i].xyz, 1.0)).xyz;
    vec3 rd = viewRayOfPixel(gl_FragCoord.xy);
    vec3 hit;
    float chord;
    if (!sphereHit(rd, centre, r, hit, chord))
        hit = dot(rd, centre) * rd; // a grazing ray rounded the other way: the outline point
    gl_FragDepth = uintBitsToFloat(texelFetch(nearest, p, 0).r);
    outColour = vec4(sphereColour(rd, hit, centre, r, velocities[i]), 1.0);
}
