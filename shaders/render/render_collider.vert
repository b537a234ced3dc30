// Collider ray marching, vertex half: the 36 vertices of the collider's grid box (from
// gl_VertexID, no vertex buffer), placed in the world by the collider's pose.
#version 450 core

#include "glsl/RenderGlsl.h"

uniform mat4 uLocalToWorld; // collider local [asset units] -> world [m]
uniform vec3 uBoxMin;       // grid box, local [asset units]
uniform vec3 uBoxMax;

out vec3 vWorld;

// Corner k of the unit cube is (k & 1, (k >> 1) & 1, (k >> 2) & 1); two triangles per face.
const int kIndices[36] = int[36](0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5);

void main() {
    int k = kIndices[gl_VertexID];
    vec3 corner = vec3(float(k & 1), float((k >> 1) & 1), float((k >> 2) & 1));
    vec4 world = uLocalToWorld * vec4(mix(uBoxMin, uBoxMax, corner), 1.0);
    vWorld = world.xyz;
    gl_Position = F.proj * (F.view * world);
}
