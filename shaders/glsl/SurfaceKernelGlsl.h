// The per-particle surface passes' inputs: the particles, and their kernels when anisotropic
// (surface_anisotropy.comp writes them; uAnisotropic false: the sphere round each particle).
#ifndef SLUICE_SHARED_SURFACE_KERNEL_GLSL_H
#define SLUICE_SHARED_SURFACE_KERNEL_GLSL_H

#include "glsl/SurfaceGlsl.h"

uniform bool uAnisotropic;
uniform bool uWeighted; // the density-normalised field's second pass: each particle's weight

layout(std430, binding = kSurfBindWeights) readonly buffer Weights { float weights[]; };

// What particle i's kernel is scaled by: 1, or in the density-normalised field's second pass
// the rest density over the particle's own (surface_density.comp).
float particleWeight(uint i) {
    return uWeighted ? weights[i] : 1.0;
}

layout(std430, binding = kSurfBindPoints) readonly buffer Points { vec4 points[]; };
layout(std430, binding = kSurfBindKernels) buffer Kernels { vec4 kernels[]; };

SurfaceKernel kernelOf(uint i) {
    if (uAnisotropic)
        return packedKernel(kernels[4u * i], kernels[4u * i + 1u], kernels[4u * i + 2u],
                            kernels[4u * i + 3u]);
    SurfaceKernel k;
    k.centre = points[i].xyz;
    k.g = mat3(1.0);
    k.extent = vec3(uSupport);
    return k;
}

#endif // SLUICE_SHARED_SURFACE_KERNEL_GLSL_H
