// GlDirectLight.cpp: per point, the terms of the batch's emitters (LightEmission.h's formulas in
// float), each counted where the map says the point is unshadowed.
layout(local_size_x = 64) in;
layout(std430, binding = 1) readonly buffer Points { vec4 points[]; };   // position, normal
layout(std430, binding = 2) buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 3) buffer Bits { uint bits[]; };
layout(std430, binding = 5) readonly buffer Classes { uint classes[]; };   // 4 a word: [tile * lights + light]
layout(std430, binding = 6) readonly buffer TileOf { uint tileOf[]; };
layout(binding = 0) uniform sampler2DArray maps;
uniform int emitterCount, pointBase, pointCount, resolution, wantBits, wordsPerPoint, useClasses, lightCount;
uniform float invRadius, texelAngle, directionalTexel, maxBiasTexels;

vec2 octahedral(vec3 v)
{
    float w = abs(v.x) + abs(v.y) + abs(v.z);
    vec2 p = v.xy / w;
    if (v.z < 0.0) {
        vec2 s = vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
        p = s * (1.0 - abs(p.yx));
    }
    return p;
}

float term(Emitter em, vec3 x, vec3 n)
{
    int type = int(em.position.w);
    if (type == kDirectional)
        return em.params.x * max(0.0, -dot(n, em.direction.xyz));
    vec3 toLight = em.position.xyz - x;
    float d2 = dot(toLight, toLight);
    if (!(d2 > 0.0))
        return 0.0;
    float d = sqrt(d2);
    vec3 l = toLight / d;
    float cosReceiver = dot(n, l);
    if (!(cosReceiver > 0.0))
        return 0.0;
    if (type == kArea) {
        float cosLight = -dot(em.direction.xyz, l);
        float facing = em.direction.w > 0.5 ? abs(cosLight) : max(0.0, cosLight);
        return em.params.x * facing * cosReceiver / max(d2, em.colour.w);
    }
    float t = em.params.x * cosReceiver / d2;
    if (em.params.y > 0.0) {
        float r = d / em.params.y;
        float window = clamp(1.0 - r * r * r * r, 0.0, 1.0);
        t *= window * window;
    }
    if (type == kSpot) {
        float cone = clamp((-dot(em.direction.xyz, l) - em.params.w) / (em.params.z - em.params.w), 0.0, 1.0);
        t *= cone * cone;
    }
    return t;
}

bool unshadowed(Emitter em, int layer, vec3 x, vec3 n)
{
    int type = int(em.position.w);
    vec2 uv;
    float depth, lateral, cosTheta;
    if (type == kDirectional) {
        vec3 u, v;
        orthoBasis(em.direction.xyz, u, v);
        uv = vec2(dot(x, u), dot(x, v)) * invRadius;
        if (any(greaterThan(abs(uv), vec2(1.0))))
            return true;   // its ray passes beside the scene's bounding sphere: nothing on it
        depth = dot(x, em.direction.xyz);
        lateral = directionalTexel;
        cosTheta = abs(dot(n, em.direction.xyz));
    } else {
        vec3 q = x - em.position.xyz;
        depth = length(q);
        if (!(depth > 0.0))
            return true;
        uv = octahedral(q);
        lateral = depth * texelAngle;
        cosTheta = abs(dot(n, q)) / depth;
    }
    ivec2 texel = clamp(ivec2(floor((uv * 0.5 + 0.5) * float(resolution))), ivec2(0), ivec2(resolution - 1));
    float nearest = texelFetch(maps, ivec3(texel, layer), 0).r;
    float tanTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta)) / max(cosTheta, 1e-6);
    return depth <= nearest + lateral * min(1.0 + tanTheta, maxBiasTexels);
}

void main()
{
    int i = pointBase + int(gl_GlobalInvocationID.x);
    if (i >= pointCount)
        return;
    vec3 x = points[2 * i].xyz, n = points[2 * i + 1].xyz;
    vec3 sum = vec3(0.0);
    uint tile = useClasses != 0 ? tileOf[i] : 0u;
    for (int k = 0; k < emitterCount; ++k) {
        int e = batch[k];
        Emitter em = emitters[e];
        float t = term(em, x, n);
        if (t <= 0.0 && wantBits == 0)
            continue;
        // Barczak's classes: unreached and shadowed tiles take nothing, lit ones no shadow test.
        uint cls = 3u;
        if (useClasses != 0) {
            uint at = tile * uint(lightCount) + uint(em.extra.x);
            cls = (classes[at / 4u] >> (8u * (at % 4u))) & 255u;
        }
        if (cls < 2u || (cls == 3u && !unshadowed(em, k, x, n)))
            continue;
        if (t > 0.0)
            sum += em.colour.rgb * t;
        if (wantBits != 0)
            bits[i * wordsPerPoint + e / 32] |= 1u << uint(e % 32);
    }
    irradiance[i] += vec4(sum, 0.0);
}
