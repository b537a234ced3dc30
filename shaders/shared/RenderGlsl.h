// GLSL helpers of the render passes: the frame block, window depth, view rays, colour maps and
// the shading every surface shares (docs/rendering.md). GLSL only.
#ifndef SLUICE_SHARED_RENDER_GLSL_H
#define SLUICE_SHARED_RENDER_GLSL_H

#include "shared/Render.h"

#ifndef __cplusplus

layout(std140, binding = kRenderBindFrame) uniform RenderFrameBlock { RenderFrame F; };

// Window depth [0, 1] of a view-space point (default glDepthRange).
float windowDepthOfView(vec3 viewPos) {
    vec4 clip = F.proj * vec4(viewPos, 1.0);
    return clamp(0.5 * (clip.z / clip.w) + 0.5, 0.0, 1.0);
}

float windowDepthOfWorld(vec3 worldPos) {
    return windowDepthOfView((F.view * vec4(worldPos, 1.0)).xyz);
}

// View-space point on the ray of window position `uv` ([0, 1]^2) at window depth `depth`.
vec3 viewOfWindow(vec2 uv, float depth) {
    vec4 clip = vec4(2.0 * uv - 1.0, 2.0 * depth - 1.0, 1.0);
    vec4 view = F.invProj * clip;
    return view.xyz / view.w;
}

// World-space direction of the view ray through window position `uv`.
vec3 worldRayOfWindow(vec2 uv) {
    vec3 viewDir = viewOfWindow(uv, 1.0);
    return normalize(mat3(F.invView) * viewDir);
}

// Sky seen along world direction `dir`: pale at the horizon, deeper blue overhead.
vec3 skyColour(vec3 dir) {
    float up = clamp(dir.y, -1.0, 1.0);
    vec3 horizon = vec3(0.78, 0.83, 0.88);
    vec3 zenith = vec3(0.36, 0.52, 0.72);
    vec3 ground = vec3(0.42, 0.42, 0.44);
    return up >= 0.0 ? mix(horizon, zenith, pow(up, 0.6)) : mix(horizon, ground, pow(-up, 0.5));
}

// Lambert + Blinn-Phong specular + hemispherical ambient, in display values.
vec3 shade(vec3 albedo, vec3 n, vec3 toEye, float specular, float shininess) {
    vec3 l = F.lightDirection;
    float diffuse = max(dot(n, l), 0.0);
    float ambient = 0.35 + 0.15 * n.y;
    vec3 h = normalize(l + toEye);
    float spec = specular * pow(max(dot(n, h), 0.0), shininess) * step(0.0, dot(n, l));
    return albedo * (ambient + 0.7 * diffuse) + vec3(spec);
}

// Colour map of t in [0, 1]: blue, cyan, green, yellow, red (a polynomial fit of Google's
// Turbo, without its near-black ends, so shading stays readable at both ends).
vec3 colourMap(float t) {
    t = 0.08 + 0.84 * clamp(t, 0.0, 1.0);
    const vec4 kr = vec4(0.13572138, 4.61539260, -42.66032258, 132.13108234);
    const vec2 kr2 = vec2(-152.94239396, 59.28637943);
    const vec4 kg = vec4(0.09140261, 2.19418839, 4.84296658, -14.18503333);
    const vec2 kg2 = vec2(4.27729857, 2.82956604);
    const vec4 kb = vec4(0.10667330, 12.64194608, -60.58204836, 110.36276771);
    const vec2 kb2 = vec2(-89.90310912, 27.34824973);
    vec4 v4 = vec4(1.0, t, t * t, t * t * t);
    vec2 v2 = v4.zw * v4.z;
    return clamp(vec3(dot(v4, kr) + dot(v2, kr2), dot(v4, kg) + dot(v2, kg2),
                      dot(v4, kb) + dot(v2, kb2)), 0.0, 1.0);
}

#endif // !__cplusplus

#endif // SLUICE_SHARED_RENDER_GLSL_H
