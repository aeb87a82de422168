// AoGlCaster.cpp: one render answers a direction d and its antipode -d (the light sphere is
// centrally symmetric): each texel keeps min(-p.d) (the surface nearest a light at +d) and
// min(p.d) (nearest -d), written by MIN blending into a two-channel float target instead of a
// depth test. In software GL the cost is the triangles' set-up, not the fragments, so one render
// for two directions halves the time (docs/ao.md).
#version 450 core
layout(location = 0) in vec3 position;
uniform vec3 centre, axisU, axisV, axisD;
uniform float invRadius;
out float along;
void main()
{
    vec3 p = position - centre;
    along = dot(p, axisD) * invRadius;   // in [-1, 1]: the bounding sphere
    // Orthographic along d; z = 0 so nothing is clipped in depth (no depth test: MIN blending).
    gl_Position = vec4(dot(p, axisU) * invRadius, dot(p, axisV) * invRadius, 0.0, 1.0);
}
