// GlDirectLight.cpp: the level's vertices (relative to the pass's origin) with their instance, the
// emitter of the batch whose map layer they are drawn into, passed on to lights_map.geom.
#version 450 core
layout(location = 0) in vec3 position;
out vec3 world;
flat out int instance;
void main()
{
    world = position;
    instance = gl_InstanceID;
}
