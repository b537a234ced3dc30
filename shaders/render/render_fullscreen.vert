// One triangle that covers the viewport, for the full-screen passes; vUv is the window
// position in [0, 1]^2.
#version 450 core

out vec2 vUv;

void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    vUv = p;
    gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
