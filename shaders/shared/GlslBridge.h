// Macros that let one header compile as C++ and as GLSL 4.50 (structs, constants, small functions).
//
// Rules for a shared header (shaders/shared/*.h):
//   - include guards, not #pragma once (GLSL has no pragma once); include this file first;
//   - wrap declarations in SLUICE_SHARED_BEGIN / SLUICE_SHARED_END (namespace sluice::shared in
//     C++, nothing in GLSL);
//   - constants are `SLUICE_CONST int kName = 3;` and work as GLSL layout qualifiers
//     (binding = kName, local_size_x = kName);
//   - std430 structs use scalars (int, uint, float), vec2, vec3, uvec3, vec4, ivec4, uvec4 and
//     mat4, each field with its own name and meaning (no value hidden in a vector's .w); C++
//     aligns glm vectors to 4 bytes where GLSL aligns vec2 to 8 and vec3/vec4/mat4 to 16, so
//     put each vec2 at a multiple of 8, each vec3/vec4/mat4 at a multiple of 16, and follow
//     every vec3 with a 4-byte scalar (GLSL packs it into the vec3's row, as C++ does); name
//     padding (pad0, pad1, ...). Give every struct C++ static_asserts on its size and on the
//     offsets of its fields in an `#ifdef __cplusplus` block;
//   - functions shared by both languages are `SLUICE_FUNC float f(uint i) { ... }`, using only
//     operations spelled the same in both (float(x) casts, sin, sqrt, min, max, abs, dot,
//     floor, clamp; ivec3 beside the struct types);
//   - C++-only includes go inside `#ifdef __cplusplus` with angle brackets: quoted includes are
//     inlined into the GLSL by cmake/SluiceEmbedScript.cmake wherever they appear.
// Keep these files ASCII: GLSL compilers may reject other bytes, even in comments.
#ifndef SLUICE_SHARED_GLSL_BRIDGE_H
#define SLUICE_SHARED_GLSL_BRIDGE_H

#ifdef __cplusplus

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace sluice::shared {
// GLSL type names for shared declarations. glm's vectors and mat4 hold the same tightly packed
// floats as their GLSL counterparts; only their alignment differs (see the rules above).
using uint = std::uint32_t;
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using ivec3 = glm::ivec3;
using uvec3 = glm::uvec3;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
// GLSL built-ins, so shared function bodies resolve to the float overloads.
using glm::clamp;
using glm::dot;
using glm::floor;
using glm::max;
using glm::min;
using std::abs;
using std::sin;
using std::cos;
using std::sqrt;
} // namespace sluice::shared

#define SLUICE_SHARED_BEGIN namespace sluice::shared {
#define SLUICE_SHARED_END }
#define SLUICE_CONST inline constexpr
#define SLUICE_FUNC inline
#define SLUICE_STRINGIFY_IMPL(x) #x
/// String literal of a macro's expansion, e.g. a GLSL identifier named once for both languages.
#define SLUICE_STRINGIFY(x) SLUICE_STRINGIFY_IMPL(x)

#else // GLSL

#define SLUICE_SHARED_BEGIN
#define SLUICE_SHARED_END
#define SLUICE_CONST const
#define SLUICE_FUNC

#endif

#endif // SLUICE_SHARED_GLSL_BRIDGE_H
