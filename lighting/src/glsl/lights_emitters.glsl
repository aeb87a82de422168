// GlDirectLight.cpp: the emitters (LightEmission.h's lights as float records), shared by the map
// and shading programs after their "#version" line.
struct Emitter { vec4 position, direction, params, colour, extra; };
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
// The emitters of this pass; with maps, emitter batch[k]'s map is layer k.
layout(std430, binding = 4) readonly buffer Batch { int batch[]; };
const int kPoint = 0, kSpot = 1, kDirectional = 2, kArea = 3;
// The directional map's axes: the same in both programs.
void orthoBasis(vec3 d, out vec3 u, out vec3 v)
{
    vec3 helper = abs(d.x) < 0.6 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    u = normalize(cross(helper, d));
    v = cross(d, u);
}
