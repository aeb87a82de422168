// ViewportRenderer.cpp: the level's vertices, with the cutaway and the objects the designer hid
// clipped by clip distances (which keep early depth tests).
#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in uint object;
layout(location = 3) in vec2 aoUv;   // where the vertex lies in the AO light map; x < 0: none
uniform mat4 viewProj;
uniform vec3 eye;
uniform vec3 viewForward;
uniform float cutDepth;      // cutaway: nearer than this along viewForward is clipped,
uniform float cutHeight;     // and above this height (clip distances keep early depth tests)
uniform int hideOn;          // objects the designer hid (ObjectFlags.h): clipped whole
layout(binding = 5) uniform usamplerBuffer hiddenObjects;
out vec3 vPosition;
out vec3 vNormal;
out vec2 vAoUv;
flat out uint vObject;
void main() {
    vAoUv = aoUv;
    vPosition = position;
    vNormal = normal;
    vObject = object;
    gl_ClipDistance[0] = cutHeight - position.y;
    gl_ClipDistance[1] = dot(position - eye, viewForward) - cutDepth;
    gl_ClipDistance[2] = hideOn != 0 && texelFetch(hiddenObjects, int(object)).r != 0u ? -1.0 : 1.0;
    gl_Position = viewProj * vec4(position, 1.0);
}
