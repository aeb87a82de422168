// ViewportRenderer.cpp: ray k of the subset (raySubset() in C++ computes the same pairs).
#version 450 core
uniform mat4 viewProj;
uniform vec3 sourceCorner, sourceU, sourceV;
uniform ivec2 sourceGrid;
uniform vec3 receiverCorner, receiverU, receiverV;
uniform ivec2 receiverGrid;
uniform uint receivers, receiverStride, sourceStride;
uniform int showBlocked;
uniform vec4 freeColour, blockedColour, stopColour;
// useEnds: a blocked ray ends at its first stop (ends[k], a fraction of the way to the receiver).
// marks: one vertex per ray, a dot at that stop (clipped for free rays and rays stopped nowhere).
uniform int useEnds, marks;
layout(binding = 2) uniform samplerBuffer ends;
// The drawn rays, listed on the CPU once per answer (never the whole map: a 512x512 receiver's
// is 32 MB). indirect: vertex pair n draws ray rays[n], the free rays of the subset (blocked rays
// hidden: none of them costs vertex work). Otherwise ray k = n, blocked where bit k of rays is set.
// disagreement: listed like indirect, each entry k | class << 30 (k < 2^30: 1024 x 1024^2 rays at
// most), the class colouring it: 1 false-blocked, 2 false-free, 3 a tie (disagreementDrawnRays).
uniform int indirect, disagreement;
uniform vec4 falseBlockedColour, falseFreeColour, tieColour;
layout(binding = 0) uniform usamplerBuffer rays;
out vec4 vColour;
uint mixBits(uint x) {
    x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
    return x;
}
vec3 samplePoint(vec3 corner, vec3 u, vec3 v, ivec2 grid, uint index) {
    uint a = index % uint(grid.x), b = index / uint(grid.x);
    return corner + (float(a) + 0.5) / float(grid.x) * u + (float(b) + 0.5) / float(grid.y) * v;
}
void main() {
    uint id = marks != 0 ? uint(gl_VertexID) : uint(gl_VertexID) >> 1;
    uint entry = indirect != 0 ? texelFetch(rays, int(id)).r : id;
    uint kind = disagreement != 0 ? entry >> 30 : 0u;
    uint k = disagreement != 0 ? entry & 0x3fffffffu : entry;
    uint jk = k % receivers, ik = k / receivers;
    uint j = jk * receiverStride + (receiverStride > 1u ? mixBits(jk) % receiverStride : 0u);
    uint i = ik * sourceStride + (sourceStride > 1u ? mixBits(j ^ 0x5bd1e995u) % sourceStride : 0u);
    bool blocked = indirect == 0 && ((texelFetch(rays, int(k >> 5)).r >> (k & 31u)) & 1u) != 0u;
    vec3 s = samplePoint(sourceCorner, sourceU, sourceV, sourceGrid, i);
    vec3 r = samplePoint(receiverCorner, receiverU, receiverV, receiverGrid, j);
    float stop = (blocked && useEnds != 0) ? texelFetch(ends, int(k)).r : 1.0;
    // The dot sits a hair in front of the surface it marks, so the depth test keeps it.
    vec3 p = marks != 0 ? mix(s, r, max(stop - 0.002, 0.0)) : (gl_VertexID & 1) != 0 ? mix(s, r, stop) : s;
    vColour = marks != 0       ? stopColour
              : kind == 1u     ? falseBlockedColour
              : kind == 2u     ? falseFreeColour
              : kind == 3u     ? tieColour
              : blocked        ? blockedColour
                               : freeColour;
    bool clipped = (blocked && showBlocked == 0) || (marks != 0 && !(blocked && stop < 1.0));
    gl_Position = clipped ? vec4(2.0, 2.0, 2.0, 1.0) : viewProj * vec4(p, 1.0);
    gl_PointSize = 4.0;
}
