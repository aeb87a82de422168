// GlDirectLight.cpp: each map texel keeps the nearest surface: a directional map the depth along
// the light (in toPoint.x), an emitter's the distance.
in vec3 toPoint;
layout(location = 0) out float nearest;
void main()
{
    nearest = int(emitters[batch[gl_Layer]].position.w) == kDirectional ? toPoint.x : length(toPoint);
}
