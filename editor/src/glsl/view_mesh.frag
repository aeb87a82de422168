// ViewportRenderer.cpp: the level's surfaces: headlight shading, the selected object, the PVS
// debugger's culled objects, AO or the lit view's map through level_shading.glsl (which comes
// first, after "#version").
in vec3 vPosition;
in vec3 vNormal;
in vec2 vAoUv;
flat in uint vObject;
uniform vec3 eye;
uniform vec3 viewForward;
uniform int orthographic;    // the headlight is the view direction, the same over the whole view
uniform int pvsOn;           // the PVS debugger: scene-file objects the current cell cannot see
layout(binding = 4) uniform usamplerBuffer pvsCulled;
uniform vec3 baseColour;
uniform int selected;        // object id, -1 for none
uniform vec4 flatColour;     // alpha > 0: wireframe pass, no shading
layout(location = 0) out vec4 colour;
layout(location = 1) out vec4 surface;   // LevelRelight's: map uv, headlight, 1 where the map shades it
layout(location = 2) out vec4 unlit;     // ... and the colour before light
void main() {
    if (flatColour.a > 0.0) {
        colour = flatColour;
        surface = vec4(-1.0, -1.0, 0.0, 0.0);
        unlit = vec4(0.0);
        return;
    }
    vec3 toEye = orthographic != 0 ? -viewForward : normalize(eye - vPosition);
    vec3 n = normalize(vNormal);
    if (dot(n, toEye) < 0.0) n = -n;           // both faces block rays; both are shaded
    float light = 0.25 + 0.6 * max(dot(n, toEye), 0.0) + 0.15 * (0.5 + 0.5 * n.y);
    // The inside of a solid, seen where the section cut opened it, reads as the cut's section
    // (darker), so walls stand out from floors in a plan view, where every face would be as bright.
    if (!gl_FrontFacing) light *= 0.55;
    vec3 c = baseColour;
    uint tint = pvsOn != 0 ? texelFetch(pvsCulled, int(vObject)).r : 0u;   // ViewportRenderer::setPvsCulled's classes
    if (tint == 1u) c = mix(c, vec3(0.85, 0.1, 0.45), 0.7);
    else if (tint == 2u) c = mix(c, vec3(1.0, 0.85, 0.2), 0.55);
    else if (tint == 3u) c = mix(c, vec3(0.55, 0.35, 0.95), 0.6);
    else if (tint == 4u) c *= 0.35;
    // The selection's tint is faint where AO shades the level: a strong one would hide the very
    // shading the designer selected the object to see (View > AO of Selected Object Only).
    if (int(vObject) == selected) c = mix(c, vec3(1.0, 0.55, 0.1), aoOn != 0 ? 0.2 : 0.6);
    surface = vec4(vAoUv, light, aoOn != 0 ? 1.0 : 0.0);
    unlit = vec4(c, 1.0);
    colour = vec4(shadeLevel(c, light, vAoUv), 1.0);
}
