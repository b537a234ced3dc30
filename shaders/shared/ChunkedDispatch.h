// Group offset for compute shaders that Program::dispatchChunked splits into bounded dispatches.
//
// GLSL use: include this header and index work with SLUICE_GLOBAL_ID instead of
// gl_GlobalInvocationID. A plain dispatch leaves the offset at zero, so the same shader runs
// both ways. Guard the tail with the item count: the last group may run past it.
#ifndef SLUICE_SHARED_CHUNKED_DISPATCH_H
#define SLUICE_SHARED_CHUNKED_DISPATCH_H

#include "shared/GlslBridge.h"

/// GLSL name of the uvec3 uniform holding the first work group of the current chunk.
#define SLUICE_GROUP_OFFSET_UNIFORM sluiceGroupOffset

#ifdef __cplusplus

SLUICE_SHARED_BEGIN
/// Name of the group-offset uniform, for Program::dispatchChunked.
SLUICE_CONST const char* kGroupOffsetUniform = SLUICE_STRINGIFY(SLUICE_GROUP_OFFSET_UNIFORM);
SLUICE_SHARED_END

#else // GLSL

uniform uvec3 SLUICE_GROUP_OFFSET_UNIFORM;
// A macro, not a function, so it may be included before the local_size layout line
// (gl_WorkGroupSize may only be used after it).
#define SLUICE_GLOBAL_ID (gl_GlobalInvocationID + SLUICE_GROUP_OFFSET_UNIFORM * gl_WorkGroupSize)

#endif

#endif // SLUICE_SHARED_CHUNKED_DISPATCH_H
