// The reconstructed surface mesh: the water colour lit as the colliders are, with the sky
// reflected by Schlick's Fresnel term, so its shape reads and it looks like water.
#version 450 core

#include "glsl/RenderGlsl.h"

in vec3 vWorld;
in vec3 vNormal;
layout(location = 0) out vec4 outColour;

void main() {
    vec3 toEye = normalize(F.eye - vWorld);
    vec3 n = normalize(vNormal);
    if (dot(n, toEye) < 0.0)
        n = -n; // the inside of the sheet, seen through a gap
    vec3 colour = shade(F.waterColour, n, toEye, 0.6, 80.0);
    float f0 = F.fluidFresnelF0;
    float fresnel = f0 + (1.0 - f0) * pow(1.0 - max(dot(n, toEye), 0.0), 5.0);
    colour = mix(colour, skyColour(reflect(-toEye, n)), fresnel);
    outColour = vec4(colour, 1.0);
}
