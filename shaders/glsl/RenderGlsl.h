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

// Unit view-space direction of the ray from the eye through window position `pixel` [pixels]
// (a pixel centre is its integer corner + 0.5), for the symmetric perspective projection the
// cameras use: cheaper than unprojecting through invProj, and the same in every shader.
vec3 viewRayOfPixel(vec2 pixel) {
    vec2 ndc = 2.0 * pixel * F.invViewportSize - 1.0;
    return normalize(vec3(ndc.x / F.proj[0][0], ndc.y / F.proj[1][1], -1.0));
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

// Where the view ray along unit direction rd (from the eye, the view-space origin) first meets
// the sphere of view-space centre `centre` and radius r: false when it misses. `chord` is the
// ray's length inside the sphere [m].
bool sphereHit(vec3 rd, vec3 centre, float r, out vec3 hit, out float chord) {
    float b = dot(rd, centre);
    float c = dot(centre, centre) - r * r;
    float disc = b * b - c;
    hit = vec3(0.0);
    chord = 0.0;
    if (disc < 0.0)
        return false;
    float s = sqrt(disc);
    hit = (b - s) * rd;
    chord = 2.0 * s;
    return true;
}

// The colour of a particle's sphere where the view ray along rd hits it, at view-space point
// `hit` (water, speed or density error, F.colourMode), from its world velocity with the density
// error C_i in w.
vec3 sphereColour(vec3 rd, vec3 hit, vec3 centre, float r, vec4 velocity) {
    vec3 n = mat3(F.invView) * ((hit - centre) / r);
    vec3 toEye = -(mat3(F.invView) * rd);
    uint mode = F.colourMode;
    if (mode == kColourSpeed)
        return shade(colourMap(length(velocity.xyz) / F.speedRange), n, toEye, 0.25, 40.0);
    if (mode == kColourDensityError)
        return shade(colourMap(velocity.w / F.densityErrorRange), n, toEye, 0.25, 40.0);
    vec3 colour = shade(F.waterColour, n, toEye, 0.6, 60.0);
    // A little sky reflected at grazing angles (Schlick's Fresnel term, F0 = 0.02).
    // (n is a unit vector to rounding: 1 - n.toEye may come out a hair below 0, and pow of a
    // negative base is undefined, black on some GPUs.)
    float fresnel = 0.02 + 0.98 * pow(clamp(1.0 - dot(n, toEye), 0.0, 1.0), 5.0);
    return mix(colour, skyColour(reflect(-toEye, n)), 0.6 * fresnel);
}

// The camera-facing square a particle's sphere is drawn on, as four view-space corners: in the
// plane through the sphere's front point (normal to the eye direction), just large enough to
// hold the sphere's exact perspective outline, so every fragment's ray that hits the sphere
// crosses the square, and the hit lies behind it along the ray (conservative depth). False when
// the eye is inside the sphere or the position is not finite.
bool sphereSquare(vec3 centre, float r, out vec3 origin, out vec3 u, out vec3 v) {
    float d = length(centre);
    origin = centre;
    u = vec3(0.0);
    v = vec3(0.0);
    if (!(d > 1.001 * r))
        return false;
    vec3 w = centre / d;
    vec3 helper = abs(w.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    // The cone of rays from the eye tangent to the sphere (half-angle asin(r / d)) cuts the
    // plane at distance d - r in a circle of radius (d - r) r / sqrt(d^2 - r^2).
    float halfSize = (d - r) * r / sqrt(d * d - r * r);
    u = halfSize * normalize(cross(helper, w));
    v = cross(w, u);
    origin = centre - r * w;
    return true;
}

#endif // !__cplusplus

#endif // SLUICE_SHARED_RENDER_GLSL_H
