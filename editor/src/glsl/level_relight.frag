// LevelRelight.cpp: every pixel the light map shades, lit again from the surfaces the level's draw
// left (its map uv, headlight term and colour before light) with level_shading.glsl.
layout(binding = 6) uniform sampler2D surfaceMap;   // (map uv, headlight, 1 where the map shades it)
layout(binding = 7) uniform sampler2D baseMap;      // the colour before light
layout(location = 0) out vec4 colour;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 s = texelFetch(surfaceMap, p, 0);
    if (s.w == 0.0) discard;   // background, wireframe, or drawn without the map: kept
    colour = vec4(shadeLevel(texelFetch(baseMap, p, 0).rgb, s.z, s.xy), 1.0);
}
