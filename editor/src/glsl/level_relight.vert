// LevelRelight.cpp: one triangle over the whole target.
#version 450 core
void main() {   // one triangle over the whole target
    vec2 p = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
}
