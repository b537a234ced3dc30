// Rendering data shared by C++ and GLSL: the per-frame uniform block, binding indices and the
// colour modes of the sphere impostors (docs/rendering.md).
#ifndef SLUICE_SHARED_RENDER_H
#define SLUICE_SHARED_RENDER_H

#include "shared/GlslBridge.h"

SLUICE_SHARED_BEGIN

// Uniform block binding of RenderFrame (every render program).
SLUICE_CONST uint kRenderBindFrame = 0;
// Shader storage bindings of the particle programs: the simulation's buffers, read only.
SLUICE_CONST uint kRenderBindPositions = 0;  ///< vec4 x (xyz) [m]
SLUICE_CONST uint kRenderBindVelocities = 1; ///< vec4 v (xyz) [m/s], w = density error C_i
// Statistics reduction (render_stats.comp).
SLUICE_CONST uint kRenderBindStats = 2;      ///< RenderStats, accumulated with atomics
SLUICE_CONST uint kRenderStatsLocalSize = 128;
/// Fixed-point scale of the density-error sum (integer adds are order-free).
SLUICE_CONST float kRenderStatsFixedScale = 65536.0;

// Texture units of the full-screen passes.
SLUICE_CONST uint kRenderUnitSdf = 0;         ///< sampler3D: one collider's distances
SLUICE_CONST uint kRenderUnitSceneColour = 1; ///< sampler2D: the opaque scene, RGBA8
SLUICE_CONST uint kRenderUnitSceneDepth = 2;  ///< sampler2D: its depth, [0, 1] window depth
SLUICE_CONST uint kRenderUnitFluidDepth = 3;  ///< sampler2D: fluid view depth [m], 0 = none
SLUICE_CONST uint kRenderUnitThickness = 4;   ///< sampler2D: fluid thickness [m]

// Colour modes of the particles (RenderFrame.particle.y).
SLUICE_CONST uint kColourWater = 0;        ///< shaded water blue
SLUICE_CONST uint kColourSpeed = 1;        ///< |v| through a colour map, 0 .. particle.z [m/s]
SLUICE_CONST uint kColourDensityError = 2; ///< C_i through a colour map, 0 .. particle.w

/// What every render pass of one frame reads (std140; vec4 and mat4 only, so std430 agrees).
struct RenderFrame {
    mat4 view;        ///< world -> view [m]
    mat4 proj;        ///< view -> clip (OpenGL, depth range [-1, 1])
    mat4 invView;     ///< view -> world
    mat4 invProj;     ///< clip -> view
    vec4 viewport;    ///< width, height [pixels], 1 / width, 1 / height
    vec4 eye;         ///< camera position, world [m] xyz; near plane [m] in w
    vec4 light;       ///< unit direction towards the light, world xyz; far plane [m] in w
    vec4 particle;    ///< radius [m], colour mode, speed of the top colour [m/s], density error
                      ///< of the top colour
    vec4 floorPlane;  ///< floor height y [m], checker size [m], 1 if the floor is drawn, unused
    vec4 water;       ///< water colour rgb (display values), unused w
    vec4 fluid;       ///< fluid surface: absorption per metre of thickness, refraction offset
                      ///< [pixels per m], Fresnel F0, sphere radius of its depth and thickness
                      ///< passes [m]
    uvec4 counts;     ///< particle count, unused yzw
};

/// What render_stats.comp accumulates over every particle.
struct RenderStats {
    uint errorLo;      ///< sum of C_i * kRenderStatsFixedScale, low 32 bits
    uint errorHi;      ///< high 32 bits
    uint errorMaxBits; ///< floatBitsToUint(max C_i) (C_i >= 0, so uint order is float order)
    uint speedMaxBits; ///< floatBitsToUint(max |v|) [m/s]
};

SLUICE_SHARED_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(sluice::shared::RenderFrame) == 4 * 64 + 8 * 16, "RenderFrame layout");
static_assert(offsetof(sluice::shared::RenderFrame, viewport) == 256, "RenderFrame layout");
static_assert(offsetof(sluice::shared::RenderFrame, counts) == 368, "RenderFrame layout");
static_assert(sizeof(sluice::shared::RenderStats) == 16, "RenderStats layout");
#endif

#endif // SLUICE_SHARED_RENDER_H
