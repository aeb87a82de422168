// ViewportRenderer.cpp: lines (gizmos, outlines, guides), coloured per vertex.
#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec4 colourIn;
uniform mat4 viewProj;
out vec4 vColour;
void main() { vColour = colourIn; gl_Position = viewProj * vec4(position, 1.0); }
