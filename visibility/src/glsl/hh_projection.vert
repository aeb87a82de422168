// HeckbertHerfSampler.cpp: the scene projected from one source sample onto the receiver grid.
// Clipping to the segment interiors uses clip distances on D / Sd directly: a far plane in the
// projection (z = k w - (k - 1) with k - 1 ~ 2e-6) drowns in float rounding of x and y's terms
// and lets triangles behind the receiver plane count.
#version 450 core
layout(location = 0) in vec3 aPosition;
uniform mat4 uProjection;   // world -> clip, from one source sample onto the receiver grid
uniform vec4 uDepth;        // world -> D / Sd: 1 at the source sample, 0 on the receiver plane
uniform float uNear;
out float gl_ClipDistance[2];
void main()
{
    vec4 x = vec4(aPosition, 1.0);
    gl_Position = uProjection * x;
    float depth = dot(uDepth, x);
    gl_ClipDistance[0] = depth;                  // in front of the receiver plane
    gl_ClipDistance[1] = (1.0 - uNear) - depth;  // short of the source sample
}
