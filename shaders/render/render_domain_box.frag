// The domain box's edges: a thin dark grey, so water the walls hold does not float in space.
#version 450 core

layout(location = 0) out vec4 outColour;

void main() {
    outColour = vec4(0.30, 0.33, 0.40, 1.0);
}
