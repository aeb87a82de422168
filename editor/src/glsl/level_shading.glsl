// LevelRelight.h: the uniforms `aoOn`, `litOn`, `aoMap` (binding 3) and
// `vec3 shadeLevel(vec3 base, float headlight, vec2 mapUv)`, the level's colour under the AO or lit
// map (mapUv.x < 0: outside the map). Shared by the level's draw (view_mesh.frag) and the relight
// pass (level_relight.frag), so that both give the same picture.
uniform int aoOn;            // ambient occlusion from the light map (AoPreview.h)
uniform int litOn;           // the lit view: the light map is the light (LitPreview.h)
layout(binding = 3) uniform sampler2D aoMap;
vec3 shadeLevel(vec3 c, float light, vec2 mapUv) {
    // The map has one level: an explicit lod keeps the relight pass's reads equal to the draw's.
    if (litOn != 0 && aoOn != 0) {
        // A faint headlight keeps unlit geometry readable; texels outside the map stay dark.
        vec3 lit = mapUv.x >= 0.0 ? textureLod(aoMap, mapUv, 0.0).rgb : vec3(0.0);
        return c * (0.06 * light + 1.25 * lit);
    }
    vec3 ambient = vec3(1.0);
    if (aoOn != 0 && mapUv.x >= 0.0)   // a floor, so the darkest corner still reads; HDR light clamped
        ambient = 0.3 + 0.7 * min(textureLod(aoMap, mapUv, 0.0).rgb, vec3(1.5));
    return c * light * ambient;
}
