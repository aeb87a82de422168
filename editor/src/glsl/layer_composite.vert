// RayLayer.cpp: a rectangle of the frame (NDC corners), each pixel reading the layer at its own
// place: the layer covers the same view, so a frame pixel's texture coordinate is its position
// over the size.
#version 450 core
uniform vec2 lo, hi;
void main() {
    const vec2 corners[4] = vec2[4](vec2(0, 0), vec2(1, 0), vec2(0, 1), vec2(1, 1));
    gl_Position = vec4(mix(lo, hi, corners[gl_VertexID]), 0.0, 1.0);
}
