// ViewportRenderer.cpp: lines (gizmos, outlines, guides) and rays in their vertices' colours.
#version 450 core
in vec4 vColour;
layout(location = 0) out vec4 colour;
void main() { colour = vColour; }
