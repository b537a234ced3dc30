// The particles' bounding box and their non-finite ones, for sizing the sample grid without
// reading the positions back: each work group reduces its particles in shared memory, then one
// invocation folds the group's box into SurfaceBounds with atomics on order-preserving bits
// (the same result from any order).
#version 450 core

#include "glsl/SurfaceGlsl.h"

layout(local_size_x = kSurfaceLocalSize) in;

layout(std430, binding = kSurfBindPoints) readonly buffer Points { vec4 points[]; };
layout(std430, binding = kSurfBindBounds) buffer Bounds { SurfaceBounds bounds; };

shared vec3 groupLo[kSurfaceLocalSize];
shared vec3 groupHi[kSurfaceLocalSize];

// Unsigned integers that order as the floats do.
uint orderedBits(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    uint l = gl_LocalInvocationID.x;
    vec3 lo = vec3(uintBitsToFloat(0x7f800000u)); // +infinity: no particle yet
    vec3 hi = -lo;
    if (i < uCount) {
        vec3 p = points[i].xyz;
        // Exponent bits all set: NaN or infinite (by the bits, as compilers may fold isnan).
        uvec3 exponent = floatBitsToUint(p) & 0x7f800000u;
        if (any(equal(exponent, uvec3(0x7f800000u)))) {
            atomicAdd(bounds.nonFinite, 1u);
            atomicMin(bounds.firstNonFinite, i);
        } else {
            lo = p;
            hi = p;
        }
    }
    groupLo[l] = lo;
    groupHi[l] = hi;
    barrier();
    for (uint half_ = kSurfaceLocalSize / 2u; half_ > 0u; half_ /= 2u) {
        if (l < half_) {
            groupLo[l] = min(groupLo[l], groupLo[l + half_]);
            groupHi[l] = max(groupHi[l], groupHi[l + half_]);
        }
        barrier();
    }
    if (l == 0u && groupLo[0].x <= groupHi[0].x) {
        for (int k = 0; k < 3; ++k) {
            atomicMin(bounds.lo[k], orderedBits(groupLo[0][k]));
            atomicMax(bounds.hi[k], orderedBits(groupHi[0][k]));
        }
    }
}
