// Screen-space fluid surface (van der Laan, Green and Sainz 2009), shading: normals from the
// smoothed view depth, Fresnel reflection of the sky, the scene behind seen through the fluid
// with a refraction-like offset along the normal and Beer-Lambert absorption by the thickness.
// Writes every pixel: the opaque scene where there is no fluid in front of it.
#version 450 core

#include "glsl/RenderGlsl.h"

layout(binding = kRenderUnitSceneColour) uniform sampler2D uSceneColour;
layout(binding = kRenderUnitSceneDepth) uniform sampler2D uSceneDepth;
layout(binding = kRenderUnitFluidDepth) uniform sampler2D uFluidDepth;
layout(binding = kRenderUnitThickness) uniform sampler2D uThickness;

in vec2 vUv;
layout(location = 0) out vec4 outColour;

// View-space point of pixel p at view depth z [m].
vec3 viewAt(ivec2 p, float z) {
    vec3 dir = viewOfWindow((vec2(p) + 0.5) * F.invViewportSize, 1.0);
    return dir * (z / -dir.z);
}

// The difference to the neighbour on one side, or the other side when it is closer in depth or
// the first is empty (van der Laan et al. 2009, section 4.2).
vec3 edgeAware(ivec2 p, ivec2 step, vec3 centre) {
    ivec2 last = textureSize(uFluidDepth, 0) - 1;
    float zf = texelFetch(uFluidDepth, clamp(p + step, ivec2(0), last), 0).r;
    float zb = texelFetch(uFluidDepth, clamp(p - step, ivec2(0), last), 0).r;
    vec3 forward = zf > 0.0 ? viewAt(p + step, zf) - centre : vec3(0.0);
    vec3 backward = zb > 0.0 ? centre - viewAt(p - step, zb) : vec3(0.0);
    if (zf <= 0.0)
        return backward;
    if (zb <= 0.0)
        return forward;
    return abs(forward.z) <= abs(backward.z) ? forward : backward;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 scene = texelFetch(uSceneColour, p, 0);
    float sceneDepth = texelFetch(uSceneDepth, p, 0).r;
    float z = texelFetch(uFluidDepth, p, 0).r;
    vec3 pos = viewAt(p, max(z, 1e-6));
    float depth = windowDepthOfView(pos);
    if (z <= 0.0 || depth >= sceneDepth) {
        outColour = scene;
        gl_FragDepth = sceneDepth;
        return;
    }
    vec3 dx = edgeAware(p, ivec2(1, 0), pos);
    vec3 dy = edgeAware(p, ivec2(0, 1), pos);
    vec3 nView = cross(dx, dy);
    nView = length(nView) > 0.0 ? normalize(nView) : vec3(0.0, 0.0, 1.0);
    if (dot(nView, -pos) < 0.0)
        nView = -nView;
    vec3 n = mat3(F.invView) * nView;
    vec3 toEye = -normalize(mat3(F.invView) * pos);

    float thickness = texelFetch(uThickness, p, 0).r;
    vec2 offset = nView.xy * min(thickness, 0.3) * F.fluidRefraction * F.invViewportSize;
    vec3 behind = texture(uSceneColour, vUv + offset).rgb;
    // Beer-Lambert: the channels the water colour lacks are absorbed fastest.
    vec3 absorb = F.fluidAbsorption * (vec3(1.0) - F.waterColour);
    vec3 transmittance = exp(-absorb * thickness);
    vec3 body = behind * transmittance +
                shade(F.waterColour, n, toEye, 0.0, 1.0) * (vec3(1.0) - transmittance);
    float fresnel = F.fluidFresnelF0 +
                    (1.0 - F.fluidFresnelF0) * pow(clamp(1.0 - dot(n, toEye), 0.0, 1.0), 5.0);
    vec3 h = normalize(F.lightDirection + toEye);
    float specular = pow(max(dot(n, h), 0.0), 120.0);
    vec3 colour = mix(body, skyColour(reflect(-toEye, n)), fresnel) + vec3(0.8 * specular);
    outColour = vec4(colour, 1.0);
    gl_FragDepth = depth;
}
