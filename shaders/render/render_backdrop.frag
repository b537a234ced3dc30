// The backdrop: sky gradient, and a checkered floor plane (with its depth) where the scene has
// one. Drawn first, with the depth test off, so it also clears colour and depth.
#version 450 core

#include "glsl/RenderGlsl.h"

in vec2 vUv;
layout(location = 0) out vec4 outColour;

void main() {
    vec3 rd = worldRayOfWindow(vUv);
    vec3 eye = F.eye;
    vec3 colour = skyColour(rd);
    float depth = 1.0;
    float floorY = F.floorY;
    if (F.drawFloor != 0u && rd.y < -1e-4 && eye.y > floorY) {
        float t = (floorY - eye.y) / rd.y;
        vec3 p = eye + t * rd;
        float size = F.checkerSize;
        vec2 cell = floor(p.xz / size);
        float checker = mod(cell.x + cell.y, 2.0);
        vec3 albedo = mix(vec3(0.56, 0.57, 0.58), vec3(0.66, 0.67, 0.68), checker);
        vec3 lit = shade(albedo, vec3(0.0, 1.0, 0.0), -rd, 0.0, 1.0);
        // Fade into the horizon haze with distance from the eye.
        float haze = 1.0 - exp(-0.12 * t);
        colour = mix(lit, skyColour(vec3(rd.x, 0.0, rd.z)), haze);
        depth = windowDepthOfWorld(p);
    }
    outColour = vec4(colour, 1.0);
    gl_FragDepth = depth;
}
