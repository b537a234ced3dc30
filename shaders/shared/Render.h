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
// The collider programs' sparse variant (SLUICE_SPARSE_COLLIDERS): every sparse collider's
// NanoVDB grid, back to back at 32-byte aligned offsets (glsl/NanoVdbGlsl.h).
SLUICE_CONST uint kRenderBindSparse = 3;     ///< uint[]
// The small spheres' compute pass (render_splat.comp): the particles too large for it, listed
// for the impostor draw, and that draw's indirect arguments.
SLUICE_CONST uint kRenderBindSplatList = 4;  ///< uint[] particle indices
SLUICE_CONST uint kRenderBindSplatArgs = 5;  ///< SplatDrawArgs
// The reconstructed surface mesh (SurfaceMode::Mesh, render_surface_mesh.vert).
SLUICE_CONST uint kRenderBindMeshPositions = 6; ///< float x3 per vertex [m] (shared/Surface.h)
SLUICE_CONST uint kRenderBindMeshTriangles = 7; ///< uint[] three per triangle
SLUICE_CONST uint kRenderBindMeshNormals = 8;   ///< float x3 per vertex, unit
SLUICE_CONST uint kSplatLocalSize = 128;
/// Widest and tallest a sphere's square may cover on screen [pixels] and be drawn by the
/// compute pass (one invocation visits every pixel of it); larger ones are rasterised.
SLUICE_CONST uint kSplatMaxSide = 8;
// Image units of the compute pass.
SLUICE_CONST uint kRenderImageSplatDepth = 0;  ///< r32ui: nearest window depth's bits per pixel
SLUICE_CONST uint kRenderImageSplatWinner = 1; ///< r32ui: the particle of that depth, ~0u: none
SLUICE_CONST uint kRenderImageSplatThickness = 2; ///< r32ui: summed chords, kSplatThicknessScale
SLUICE_CONST uint kRenderImageFluidSmooth = 3; ///< r32f: render_fluid_smooth.comp's output depth
/// render_fluid_smooth.comp: pixels along each side of a work group's tile, and the farthest
/// tap from a pixel along each axis [pixels].
SLUICE_CONST uint kFluidSmoothTile = 16;
SLUICE_CONST uint kFluidSmoothReach = 8;
/// Fixed-point scale of the compute pass's summed thickness [1/m]: micrometres, so integer adds
/// (order-free) hold up to 4 km of water.
SLUICE_CONST float kSplatThicknessScale = 1.0e6;
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
SLUICE_CONST uint kRenderUnitSplatDepth = 5;  ///< usampler2D: render_splat.comp's nearest depths
SLUICE_CONST uint kRenderUnitSplatWinner = 6; ///< usampler2D: and the particle of each
SLUICE_CONST uint kRenderUnitSplatThickness = 7; ///< usampler2D: render_splat.comp's thickness

// Colour modes of the particles (RenderFrame.colourMode).
SLUICE_CONST uint kColourWater = 0;        ///< shaded water blue
SLUICE_CONST uint kColourSpeed = 1;        ///< |v| through a colour map, 0 .. speedRange [m/s]
SLUICE_CONST uint kColourDensityError = 2; ///< C_i through a colour map, 0 .. densityErrorRange

/// What every render pass of one frame reads. std140 and std430 agree on it: mat4s, vec2s at
/// multiples of 8, and 16-byte aligned vec3s each followed by a scalar that fills its row.
/// Offsets [bytes] on the left are checked below.
// clang-format off
struct RenderFrame {
    /*   0 */ mat4 view;    ///< world -> view [m]
    /*  64 */ mat4 proj;    ///< view -> clip (OpenGL, depth range [-1, 1])
    /* 128 */ mat4 invView; ///< view -> world
    /* 192 */ mat4 invProj; ///< clip -> view
    // Viewport.
    /* 256 */ vec2 viewportSize;    ///< width, height [pixels]
    /* 264 */ vec2 invViewportSize; ///< 1 / width, 1 / height [1/pixels]
    // Camera and light.
    /* 272 */ vec3 eye;            ///< camera position, world [m]
    /* 284 */ float nearPlane;     ///< [m]
    /* 288 */ vec3 lightDirection; ///< unit direction towards the light, world
    /* 300 */ float farPlane;      ///< [m]
    // Particles.
    /* 304 */ float particleRadius;    ///< [m]
    /* 308 */ uint colourMode;         ///< kColourWater, kColourSpeed or kColourDensityError
    /* 312 */ float speedRange;        ///< speed of the top colour [m/s]
    /* 316 */ float densityErrorRange; ///< density error C_i of the top colour
    // Floor.
    /* 320 */ float floorY;       ///< floor height [m]
    /* 324 */ float checkerSize;  ///< side of a floor checker [m]
    /* 328 */ uint drawFloor;     ///< 1 if the floor is drawn, 0 otherwise
    /* 332 */ uint particleCount; ///< particles drawn
    // Water.
    /* 336 */ vec3 waterColour;          ///< rgb (display values)
    /* 348 */ float fluidAbsorption;     ///< fluid surface: absorption per metre of thickness
    /* 352 */ float fluidRefraction;     ///< fluid surface: refraction offset [pixels per m]
    /* 356 */ float fluidFresnelF0;      ///< fluid surface: Fresnel reflectance at normal incidence
    /* 360 */ float fluidSphereRadius;   ///< sphere radius of its depth and thickness passes [m]
    /* 364 */ uint reverseOrder;  ///< 1: draw the particles last to first (nearer front to back)
};
// clang-format on

/// glDrawArraysIndirect's arguments for the listed particles: 6 vertices each.
struct SplatDrawArgs {
    uint vertexCount;
    uint instanceCount;
    uint firstVertex;
    uint baseInstance;
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
#define SLUICE_RENDER_AT(field, offset)                                                            \
    static_assert(offsetof(sluice::shared::RenderFrame, field) == (offset),                        \
                  "std140 offset of " #field)
SLUICE_RENDER_AT(invProj, 192);
SLUICE_RENDER_AT(viewportSize, 256);
SLUICE_RENDER_AT(invViewportSize, 264);
SLUICE_RENDER_AT(eye, 272);
SLUICE_RENDER_AT(nearPlane, 284);
SLUICE_RENDER_AT(lightDirection, 288);
SLUICE_RENDER_AT(farPlane, 300);
SLUICE_RENDER_AT(particleRadius, 304);
SLUICE_RENDER_AT(densityErrorRange, 316);
SLUICE_RENDER_AT(floorY, 320);
SLUICE_RENDER_AT(particleCount, 332);
SLUICE_RENDER_AT(waterColour, 336);
SLUICE_RENDER_AT(fluidAbsorption, 348);
SLUICE_RENDER_AT(fluidSphereRadius, 360);
SLUICE_RENDER_AT(reverseOrder, 364);
static_assert(sizeof(sluice::shared::RenderFrame) == 368, "std140 size of RenderFrame");
static_assert(sizeof(sluice::shared::RenderStats) == 16, "std430 size of RenderStats");
static_assert(sizeof(sluice::shared::SplatDrawArgs) == 16, "std430 size of SplatDrawArgs");
#undef SLUICE_RENDER_AT
#endif

#endif // SLUICE_SHARED_RENDER_H
