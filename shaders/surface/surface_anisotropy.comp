// Anisotropic kernels after Yu & Turk (2013), one invocation a particle: the weighted
// covariance of its neighbours within the support (w = 1 - (d / h)^3), its principal axes by
// Jacobi rotations, and from them the kernel: axes in proportion to the neighbours' standard
// deviations along them (long along a surface or a sheet, short across it), at most
// kSurfaceAnisotropyRatio between the longest and the shortest, with the sphere's volume
// (docs/surfaces.md has why these and not Yu & Turk's own scale). Its centre moves
// uCentreSmoothing of the way to the neighbours' weighted mean. The sums are fixed point, so
// the neighbours' order in the block runs (set by atomics) does not change a bit. Writes
// SurfaceKernel, packed.
#version 450 core

#include "glsl/SurfaceKernelGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

layout(std430, binding = kSurfBindBinStart) readonly buffer BinStart { uint binStart[]; };
layout(std430, binding = kSurfBindBinParticles) readonly buffer BinParticles {
    uint binParticles[];
};
layout(std430, binding = kSurfBindBinPoints) readonly buffer BinPoints { vec4 binPoints[]; };

uniform float uCentreSmoothing; // Yu & Turk's lambda: 0 keeps the particle, 1 the mean
uniform uint uBinCount;         // blocks in the grid (binStart's length)

// Fixed-point scale of the sums: terms are at most 1 (offsets in units of the support), so
// 32767 neighbours fit; a particle with more keeps the sphere.
const float kFix = 65536.0;
const int kMaxNeighbours = 32767;

int fixedOf(float v) {
    return int(round(v * kFix));
}

// Eigenvalues (the diagonal of `a` after) and eigenvectors (v's columns) of the symmetric `a`,
// by cyclic Jacobi rotations (Numerical Recipes' rotation; a 3 x 3 converges in a few sweeps).
void symmetricEigen(inout mat3 a, out mat3 v) {
    v = mat3(1.0);
    for (int sweep = 0; sweep < 6; ++sweep)
        for (int pair = 0; pair < 3; ++pair) {
            int p = pair == 2 ? 1 : 0;
            int q = pair == 0 ? 1 : 2;
            float apq = a[q][p];
            if (abs(apq) <= 1e-12 * (abs(a[p][p]) + abs(a[q][q])) + 1e-30)
                continue;
            float theta = (a[q][q] - a[p][p]) / (2.0 * apq);
            float t = (theta >= 0.0 ? 1.0 : -1.0) / (abs(theta) + sqrt(theta * theta + 1.0));
            float c = inversesqrt(t * t + 1.0);
            float s = t * c;
            vec3 ap = a[p];
            vec3 aq = a[q];
            a[p] = c * ap - s * aq;
            a[q] = s * ap + c * aq;
            for (int k = 0; k < 3; ++k) {
                float x = a[k][p];
                float y = a[k][q];
                a[k][p] = c * x - s * y;
                a[k][q] = s * x + c * y;
            }
            vec3 vp = v[p];
            vec3 vq = v[q];
            v[p] = c * vp - s * vq;
            v[q] = s * vp + c * vq;
        }
}

void main() {
    // In the bins' order: the invocations of a group share their blocks' runs.
    uint slot = SLUICE_GLOBAL_ID.x;
    if (slot >= uCount)
        return;
    uint i = binParticles[slot];
    vec3 p = binPoints[slot].xyz;
    float invH = 1.0 / uSupport;
    // The blocks the support's box overlaps (8 on average where the block is twice the
    // support, not 27).
    ivec3 lo = blockOfPoint(p - uSupport);
    ivec3 hi = blockOfPoint(p + uSupport);
    int n = 0;
    int sw = 0;
    ivec3 sd = ivec3(0);
    ivec3 sdiag = ivec3(0); // xx, yy, zz
    ivec3 soff = ivec3(0);  // xy, xz, yz
    for (int bz = lo.z; bz <= hi.z; ++bz)
        for (int by = lo.y; by <= hi.y; ++by)
            for (int bx = lo.x; bx <= hi.x; ++bx) {
                uint b = blockIndex(ivec3(bx, by, bz));
                uint end = b + 1u < uBinCount ? binStart[b + 1u] : uCount;
                for (uint k = binStart[b]; k < end; ++k) {
                    vec3 d = (binPoints[k].xyz - p) * invH;
                    float r2 = dot(d, d);
                    if (r2 >= 1.0)
                        continue;
                    float w = 1.0 - r2 * sqrt(r2);
                    vec3 wd = w * d;
                    ++n;
                    sw += fixedOf(w);
                    sd += ivec3(round(wd * kFix));
                    sdiag += ivec3(round(wd * d * kFix));
                    soff += ivec3(round(vec3(wd.x * d.y, wd.x * d.z, wd.y * d.z) * kFix));
                }
            }
    vec3 centre = p;
    mat3 g = mat3(1.0);
    vec3 extent = vec3(uSupport);
    if (n <= kMaxNeighbours && sw > 0) {
        float weight = float(sw);
        vec3 mean = vec3(sd) / weight;
        centre = p + uCentreSmoothing * uSupport * mean;
        if (n >= int(kSurfaceAnisotropyMinNeighbours)) {
            vec3 diag = vec3(sdiag) / weight - mean * mean;
            vec3 off = vec3(soff) / weight - vec3(mean.x * mean.y, mean.x * mean.z, mean.y * mean.z);
            mat3 c = mat3(diag.x, off.x, off.y, off.x, diag.y, off.z, off.y, off.z, diag.z);
            mat3 axes;
            symmetricEigen(c, axes);
            vec3 sigma = max(vec3(c[0][0], c[1][1], c[2][2]), vec3(0.0));
            float largest = max(sigma.x, max(sigma.y, sigma.z));
            if (largest > 0.0) {
                // Axes as the neighbours' standard deviations, the shortest at least 1 / ratio
                // of the longest, scaled to the sphere's volume (det G = 1).
                float ratio = kSurfaceAnisotropyRatio;
                vec3 spread = sqrt(max(sigma, vec3(largest / (ratio * ratio))));
                vec3 scale = spread / pow(spread.x * spread.y * spread.z, 1.0 / 3.0);
                g = mat3(0.0);
                extent = vec3(0.0);
                for (int a = 0; a < 3; ++a) {
                    g += outerProduct(axes[a], axes[a]) / scale[a];
                    extent += (scale[a] * axes[a]) * (scale[a] * axes[a]);
                }
                extent = uSupport * sqrt(extent);
            }
        }
    }
    kernels[4u * i] = vec4(centre, 0.0);
    kernels[4u * i + 1u] = vec4(g[0][0], g[0][1], g[0][2], g[1][1]);
    kernels[4u * i + 2u] = vec4(g[1][2], g[2][2], 0.0, 0.0);
    kernels[4u * i + 3u] = vec4(extent, 0.0);
}
