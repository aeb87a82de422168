// ViewportRenderer.cpp: the overlay: the patch's parallelogram, patch coordinates (s, t) in
// [0, 1]^2, lifted a little towards the eye. Colours come from a buffer texture, sample (a, b) at
// texel b * na + a, fetched by hand: texel (a, b) covers the cell [a/na, (a+1)/na) x
// [b/nb, (b+1)/nb) whose centre is sample (a, b) (docs/design.md §2), exactly; `smoothing`
// interpolates between sample centres instead.
#version 450 core
uniform mat4 viewProj;
uniform vec3 corner, edgeU, edgeV, lift;
out vec2 st;
void main() {
    const vec2 corners[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
    st = corners[gl_VertexID];
    gl_Position = viewProj * vec4(corner + st.x * edgeU + st.y * edgeV + lift, 1.0);
}
