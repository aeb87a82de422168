// AoGlCaster.cpp: the two depths of ao_depth.vert, kept by MIN blending.
#version 450 core
in float along;
layout(location = 0) out vec2 nearest;
void main() { nearest = vec2(-along, along); }
