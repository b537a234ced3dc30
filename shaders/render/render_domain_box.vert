// The domain box's twelve edges as 24 line vertices from gl_VertexID alone (no vertex buffer):
// edge e runs along axis e / 4, and e % 4 picks which of the four parallel edges.
#version 450 core

#include "glsl/RenderGlsl.h"

uniform vec3 uDomainMin; // [m]
uniform vec3 uDomainMax; // [m]

void main() {
    int edge = gl_VertexID / 2;
    int axis = edge / 4;
    int which = edge % 4;
    vec3 corner = vec3(0.0);
    corner[axis] = float(gl_VertexID & 1);
    corner[(axis + 1) % 3] = float(which & 1);
    corner[(axis + 2) % 3] = float((which >> 1) & 1);
    vec3 world = mix(uDomainMin, uDomainMax, corner);
    gl_Position = F.proj * F.view * vec4(world, 1.0);
}
