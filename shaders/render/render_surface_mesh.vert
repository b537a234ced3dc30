// The reconstructed surface mesh (runtime/src/surface/), drawn without a vertex buffer: vertex
// gl_VertexID is corner gl_VertexID % 3 of triangle gl_VertexID / 3, read from the mesh's own
// storage buffers.
#version 450 core

#include "shared/RenderGlsl.h"
#include "shared/Surface.h"

layout(std430, binding = kRenderBindMeshVertices) readonly buffer MeshVertices {
    SurfaceVertex meshVertices[];
};
layout(std430, binding = kRenderBindMeshTriangles) readonly buffer MeshTriangles {
    uint meshTriangles[];
};

out vec3 vWorld;
out vec3 vNormal;

void main() {
    SurfaceVertex v = meshVertices[meshTriangles[gl_VertexID]];
    vWorld = v.position.xyz;
    vNormal = v.normal.xyz;
    gl_Position = F.proj * F.view * vec4(vWorld, 1.0);
}
