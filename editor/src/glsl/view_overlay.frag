// ViewportRenderer.cpp: a patch's per-sample colours (view_overlay.vert), nearest or smoothed.
#version 450 core
in vec2 st;
uniform ivec2 grid;
uniform int smoothing;
layout(binding = 1) uniform samplerBuffer texels;
layout(location = 0) out vec4 colour;
vec4 texel(ivec2 p) {
    p = clamp(p, ivec2(0), grid - 1);
    return texelFetch(texels, p.y * grid.x + p.x);
}
void main() {
    vec2 cell = st * vec2(grid);
    if (smoothing == 0) {
        colour = vec4(texel(ivec2(floor(cell))).rgb, 1.0);
        return;
    }
    vec2 q = cell - 0.5;   // sample centres at integer q
    ivec2 i = ivec2(floor(q));
    vec2 f = q - vec2(i);
    vec4 c = mix(mix(texel(i), texel(i + ivec2(1, 0)), f.x), mix(texel(i + ivec2(0, 1)), texel(i + ivec2(1, 1)), f.x), f.y);
    colour = vec4(c.rgb, 1.0);
}
