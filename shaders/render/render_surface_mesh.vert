// The reconstructed surface mesh (runtime/src/surface/), drawn without a vertex buffer: vertex
// gl_VertexID is corner gl_VertexID % 3 of triangle gl_VertexID / 3, read from the mesh's own
// storage buffers.
#version 450 core

#include "glsl/RenderGlsl.h"
#include "shared/Surface.h"

// Positions and normals as packed float triples (std430 would pad a vec3 array to 16 bytes).
layout(std430, binding = kRenderBindMeshPositions) readonly buffer MeshPositions {
    float meshPositions[];
};
layout(std430, binding = kRenderBindMeshNormals) readonly buffer MeshNormals {
    float meshNormals[];
};
layout(std430, binding = kRenderBindMeshTriangles) readonly buffer MeshTriangles {
    uint meshTriangles[];
};

out vec3 vWorld;
out vec3 vNormal;

void main() {
    uint v = 3u * meshTriangles[gl_VertexID];
    vWorld = vec3(meshPositions[v], meshPositions[v + 1u], meshPositions[v + 2u]);
    vNormal = vec3(meshNormals[v], meshNormals[v + 1u], meshNormals[v + 2u]);
    gl_Position = F.proj * F.view * vec4(vWorld, 1.0);
}
