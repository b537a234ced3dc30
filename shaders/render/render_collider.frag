// Collider ray marching, fragment half: sphere tracing of the collider's signed distance grid
// (a 3D texture, trilinear; with SLUICE_SPARSE_COLLIDERS a NanoVDB grid read through a read
// accessor, trilinear, the march skipping the tiles outside the band a node at a time) along
// this pixel's view ray, in the collider's local frame, with the hit's window depth. Only the box face where the ray leaves the box is kept, so each pixel
// is marched once whichever faces the rasterizer produced and wherever the eye is.
//
// Containers: a surface with more of the same collider behind it on the ray (the near wall of
// a tank, of a funnel, of a tube) is "glass" when uGlassWalls is set. The opaque variant skips
// glass and shades the last surface on the ray; SLUICE_GLASS draws only the first surface when
// it is glass, translucent, after the particles, so the fluid inside a container stays visible.
#version 450 core

#include "glsl/RenderGlsl.h"

#ifdef SLUICE_SPARSE_COLLIDERS
layout(std430, binding = kRenderBindSparse) readonly buffer SparseBuf { uint sparseWords[]; };
#define pnanovdb_buf_data sparseWords
#include "glsl/NanoVdbGlsl.h"
uniform uint uGridOffset;   // the collider's grid in SparseBuf [bytes]
pnanovdb_readaccessor_t gAccessor; // set in main(), then reused by every lookup of the pixel
#else
layout(binding = kRenderUnitSdf) uniform sampler3D uSdf;
#endif
uniform mat4 uLocalToWorld; // local [asset units] -> world [m], rotation and uniform scale
uniform mat4 uWorldToLocal;
uniform vec3 uBoxMin;       // grid box, local
uniform vec3 uBoxMax;
uniform vec3 uGridOrigin;   // grid point (0, 0, 0), local
uniform vec3 uDims;         // grid points per axis
uniform float uVoxel;       // grid spacing, local units
uniform vec3 uColour;       // albedo, display values
uniform int uGlassWalls;

in vec3 vWorld;
layout(location = 0) out vec4 outColour;

const int kMaxLayers = 4;

#ifdef SLUICE_SPARSE_COLLIDERS
const int kMaxSteps = 512;

// Trilinear in the grid box, as the solver samples (glsl/PbfGlsl.h, sampleCollider).
float sdf(vec3 p) {
    vec3 g = clamp((p - uGridOrigin) / uVoxel, vec3(0.0), uDims - 1.0);
    vec3 cellLo = min(floor(g), uDims - 2.0);
    vec3 t = g - cellLo;
    ivec3 b = ivec3(cellLo);
    float v[8];
    for (int k = 0; k < 8; ++k)
        v[k] = sparseValue(gAccessor, b + ivec3(k & 1, (k >> 1) & 1, k >> 2));
    vec4 x = mix(vec4(v[0], v[2], v[4], v[6]), vec4(v[1], v[3], v[5], v[7]), t.x);
    vec2 y = mix(x.xz, x.yw, t.y);
    return mix(y.x, y.y, t.z);
}

// How far the ray may jump from p without missing a surface [local units]: when p's grid cell
// lies in an outside tile (a node or the background, all of it +band), to where the ray
// leaves the tile's cube of grid points; 0 in the band's leaves.
float emptySkip(vec3 p, vec3 rd) {
    vec3 g = (p - uGridOrigin) / uVoxel;
    ivec3 ijk = ivec3(floor(g));
    if (any(lessThan(ijk, ivec3(0))))
        return 0.0;
    pnanovdb_buf_t buf;
    int dim = int(pnanovdb_readaccessor_get_dim(PNANOVDB_GRID_TYPE_FLOAT, buf, gAccessor, ijk));
    if (dim <= 1 || !(sparseValue(gAccessor, ijk) > 0.0))
        return 0.0;
    vec3 lo = vec3(ijk & ~(dim - 1));
    vec3 hi = lo + float(dim - 1);
    vec3 far = mix(lo, hi, greaterThan(rd, vec3(0.0))); // per axis, the cube's far plane
    vec3 exitT = mix((far - g) / rd, vec3(1e30), equal(rd, vec3(0.0)));
    return max(min(min(exitT.x, exitT.y), exitT.z), 0.0) * uVoxel;
}
#else
const int kMaxSteps = 192;

float sdf(vec3 p) {
    vec3 uvw = ((p - uGridOrigin) / uVoxel + 0.5) / uDims;
    return texture(uSdf, uvw).r;
}

float emptySkip(vec3 p, vec3 rd) { return 0.0; }
#endif

vec3 sdfNormal(vec3 p) {
    float e = 0.5 * uVoxel;
    vec3 g = vec3(sdf(p + vec3(e, 0, 0)) - sdf(p - vec3(e, 0, 0)),
                  sdf(p + vec3(0, e, 0)) - sdf(p - vec3(0, e, 0)),
                  sdf(p + vec3(0, 0, e)) - sdf(p - vec3(0, 0, e)));
    return length(g) > 0.0 ? normalize(g) : vec3(0.0, 1.0, 0.0);
}

// First t >= `t` below `tEnd` where the ray enters the solid, or -1. Sphere tracing with a
// floor on the step (a quarter voxel): near a surface seen at a grazing angle the plain steps
// shrink without end; the floor may step past the surface by a little, which the hit undoes.
float nextEntry(vec3 ro, vec3 rd, float t, float tEnd) {
    for (int i = 0; i < kMaxSteps && t <= tEnd; ++i) {
        float d = sdf(ro + t * rd);
        if (d < 0.05 * uVoxel)
            return t + min(d, 0.0);
        t += max(max(d, 0.25 * uVoxel), emptySkip(ro + t * rd, rd));
    }
    return -1.0;
}

// First t >= `t` where the ray is clearly outside the solid again (tEnd at most), far enough
// from the surface that nextEntry does not find the same surface again. Overshooting the exit
// a little is harmless here, so the steps are at least half a voxel.
float nextExit(vec3 ro, vec3 rd, float t, float tEnd) {
    for (int i = 0; i < kMaxSteps && t <= tEnd; ++i) {
        float d = sdf(ro + t * rd);
        if (d > 0.2 * uVoxel)
            return t;
        t += max(-d, 0.5 * uVoxel);
    }
    return tEnd;
}

// Whether more of the collider lies on the ray behind the surface entered at `t`.
bool hasMoreBehind(vec3 ro, vec3 rd, float t, float tEnd, out float next) {
    float leave = nextExit(ro, rd, t + 0.1 * uVoxel, tEnd);
    next = leave < tEnd ? nextEntry(ro, rd, leave, tEnd) : -1.0;
    return next >= 0.0;
}

void main() {
#ifdef SLUICE_SPARSE_COLLIDERS
    gAccessor = sparseAccessor(uGridOffset);
#endif
    vec3 eyeLocal = (uWorldToLocal * vec4(F.eye, 1.0)).xyz;
    vec3 fragLocal = (uWorldToLocal * vec4(vWorld, 1.0)).xyz;
    vec3 rd = normalize(fragLocal - eyeLocal);
    vec3 inv = 1.0 / rd;
    vec3 ta = (uBoxMin - eyeLocal) * inv;
    vec3 tb = (uBoxMax - eyeLocal) * inv;
    vec3 tLo = min(ta, tb);
    vec3 tHi = max(ta, tb);
    float t0 = max(max(tLo.x, tLo.y), max(tLo.z, 0.0));
    float t1 = min(min(tHi.x, tHi.y), tHi.z);
    float tFrag = length(fragLocal - eyeLocal);
    if (t1 <= t0 || abs(tFrag - t1) > abs(tFrag - t0))
        discard; // an entry face: the exit face of this pixel marches instead

    float t = nextEntry(eyeLocal, rd, t0, t1);
    if (t < 0.0)
        discard;
#if defined(SLUICE_GLASS)
    float next;
    if (uGlassWalls == 0 || !hasMoreBehind(eyeLocal, rd, t, t1, next))
        discard;
#else
    for (int layer = 1; layer < kMaxLayers && uGlassWalls != 0; ++layer) {
        float next;
        if (!hasMoreBehind(eyeLocal, rd, t, t1, next))
            break;
        t = next;
    }
#endif
    vec3 p = eyeLocal + t * rd;
    vec3 nLocal = sdfNormal(p);
    vec3 n = normalize(mat3(uLocalToWorld) * nLocal);
    vec3 world = (uLocalToWorld * vec4(p, 1.0)).xyz;
    vec3 toEye = normalize(F.eye - world);
    gl_FragDepth = windowDepthOfWorld(world);
#if defined(SLUICE_GLASS)
    float facing = abs(dot(n, toEye));
    float fresnel = 0.04 + 0.96 * pow(clamp(1.0 - facing, 0.0, 1.0), 5.0); // facing may round past 1
    vec3 tint = mix(uColour, vec3(0.85, 0.9, 0.95), 0.6);
    vec3 colour = mix(shade(tint, n, toEye, 0.8, 80.0), skyColour(reflect(-toEye, n)), fresnel);
    outColour = vec4(colour, 0.14 + 0.5 * fresnel);
#else
    // Ambient occlusion from the field itself: how far the surface is from other surfaces.
    float probe = 3.0 * uVoxel;
    float occlusion = clamp(sdf(p + probe * nLocal) / probe, 0.35, 1.0);
    outColour = vec4(shade(uColour, n, toEye, 0.15, 24.0) * occlusion, 1.0);
#endif
}
