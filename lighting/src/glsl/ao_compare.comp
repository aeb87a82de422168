// AoGlCaster.cpp: per point, whether the depth map of direction d (or of -d) holds a surface nearer
// than the point: one dispatch per pair, as a point faces at most one of d and -d.
#version 450 core
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Origins { vec4 origins[]; };
layout(std430, binding = 1) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 2) buffer Bits { uint bits[]; };
layout(binding = 0) uniform sampler2D nearestMap;
uniform vec3 centre, axisU, axisV, axisD;
uniform float invRadius, texelWorld, maxBiasTexels;
uniform int resolution, pointCount, wordsPerPoint;
uniform int directionPos, directionNeg;   // indices of d and -d; -1: not asked for in this call
void main()
{
    int i = int(gl_GlobalInvocationID.x);
    if (i >= pointCount)
        return;
    vec3 n = normals[i].xyz;
    float c = dot(n, axisD);
    int direction = c > 0.0 ? directionPos : c < 0.0 ? directionNeg : -1;
    if (direction < 0)
        return;   // facing directions only (zero normals face none)
    c = abs(c);
    vec3 p = origins[i].xyz - centre;
    vec2 ndc = vec2(dot(p, axisU), dot(p, axisV)) * invRadius;
    ivec2 texel = clamp(ivec2((ndc * 0.5 + 0.5) * float(resolution)), ivec2(0), ivec2(resolution - 1));
    vec2 nearest = texelFetch(nearestMap, texel, 0).rg;
    float along = dot(p, axisD) * invRadius;
    // The point's distance from the light's side, and the surface nearest the light in its texel.
    float depth = direction == directionPos ? -along : along;
    float mapDepth = direction == directionPos ? nearest.r : nearest.g;
    float tanTheta = sqrt(max(0.0, 1.0 - c * c)) / c;
    float bias = texelWorld * min(1.0 + tanTheta, maxBiasTexels) * invRadius;
    if (depth <= mapDepth + bias)
        atomicOr(bits[i * wordsPerPoint + direction / 32], 1u << uint(direction % 32));
}
