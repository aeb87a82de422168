// GlBitmaskSampler.cpp: each occluder's influence region, drawn as a quad: receiver samples
// a0..a1 x b0..b1.
#version 450 core
uniform isamplerBuffer uRegions;
uniform ivec2 uReceiverGrid;
flat out int vPolygon;
void main()
{
    ivec4 region = texelFetch(uRegions, gl_InstanceID);
    vec2 pixel = vec2((gl_VertexID & 1) != 0 ? region.y + 1 : region.x, (gl_VertexID & 2) != 0 ? region.w + 1 : region.z);
    gl_Position = vec4(pixel / vec2(uReceiverGrid) * 2.0 - 1.0, 0.0, 1.0);
    vPolygon = gl_InstanceID;
}
