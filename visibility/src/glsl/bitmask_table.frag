// GlBitmaskSampler.cpp, table mode (§5): the Hough table of HoughMaskTable, texel (i, k) at buffer
// texels (k * width + i) * TARGETS + target, each 128 source bits in the render targets' order.
// Every occluder is drawn; those reaching a receiver sample's distance are clipped per sample.
// The placeholder at the end of main() becomes the writes of the mask to the render targets.
uniform usamplerBuffer uTable;
uniform ivec2 uTableSize;             // (angles, distances)
const float kPi = 3.14159265358979;
const float kMaxDistance = 0.70710678118654752;   // sqrt(2) / 2

int clipPolygon(inout vec3 p[8], int n, vec4 plane)
{
    vec3 q[8];
    int m = 0;
    for (int i = 0; i < n; ++i) {
        vec3 a = p[i], b = p[(i + 1) % n];
        float da = dot(plane.xyz, a) + plane.w, db = dot(plane.xyz, b) + plane.w;
        if (da > 0.0) q[m++] = a;
        if ((da > 0.0) != (db > 0.0) && m < 8) q[m++] = a + (b - a) * (da / (da - db));
    }
    p = q;
    return m;
}

// ANDs into mask the entry of the texel nearest to the line with left normal n (unit) at signed
// distance dist from the source centre: HoughMaskTable::lookup's indexing (theta wraps, r clamps).
void andTexel(vec2 n, float dist)
{
    float angle = atan(n.y, n.x);   // [-pi, pi]
    int i = int(floor((angle + kPi) / (2.0 * kPi) * float(uTableSize.x)));
    i = i < 0 ? i + uTableSize.x : (i >= uTableSize.x ? i - uTableSize.x : i);
    int k = clamp(int(floor((dist + kMaxDistance) / (2.0 * kMaxDistance) * float(uTableSize.y))), 0, uTableSize.y - 1);
    int base = (k * uTableSize.x + i) * TARGETS;
    for (int t = 0; t < TARGETS; ++t) {
        uvec4 bits = texelFetch(uTable, base + t);
        mask[4 * t] &= bits.x; mask[4 * t + 1] &= bits.y; mask[4 * t + 2] &= bits.z; mask[4 * t + 3] &= bits.w;
    }
}

// The CPU's tableMask: the AND of the masks of the backprojection's edges, inside on the left of
// each. Each edge's line on the source plane (d = 0) comes from the plane through r and the 3D
// edge, N = (p_k - r) x (p_i - r): the line is N.xy . X = N . r and the left normal of the
// backprojected edge from p_k to p_i is -N.xy. The orientation is the polygon's seen from r,
// found once for all edges; zero: seen edge-on, no inside.
void tableMask(vec3 p[8], int n, vec3 r, vec2 shift)
{
    vec3 g = vec3(0.0);
    for (int i = 0; i < n; ++i) g += p[i];
    g /= float(n);
    vec3 m = vec3(0.0);   // Newell normal of the clipped polygon
    for (int i = 0, k = n - 1; i < n; k = i++) m += cross(p[k] - g, p[i] - g);
    float orientation = dot(m, r - g);
    for (int w = 0; w < 4 * TARGETS; ++w) mask[w] = orientation == 0.0 ? 0u : 0xffffffffu;
    if (orientation == 0.0) return;
    float counterClockwise = orientation > 0.0 ? 1.0 : -1.0;
    bool anyEdge = false;
    for (int i = 0, k = n - 1; i < n; k = i++) {
        vec3 normal = counterClockwise * cross(p[k] - r, p[i] - r);
        float length2 = length(normal.xy);
        if (length2 == 0.0) continue;   // both ends backproject to one point: the CPU skips it
        vec2 left = -normal.xy / length2;
        float dist = -dot(normal, r) / length2 - dot(left, vec2(0.5) + shift);
        andTexel(left, dist);
        anyEdge = true;
    }
    if (!anyEdge)
        for (int w = 0; w < 4 * TARGETS; ++w) mask[w] = 0u;
}

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int j = pixel.y * uReceiverGrid.x + pixel.x;
    vec3 r = samples[3 * j].xyz;
    vec2 shift = samples[3 * j + 2].xy;
    int n = polygons[vPolygon].info.x;
    vec3 p[8];
    for (int i = 0; i < 8; ++i) p[i] = i < n ? polygons[vPolygon].hi[i].xyz : vec3(0.0);
    if (polygons[vPolygon].info.w != 0) {   // points at or beyond this sample's distance lie on none of its rays
        n = clipPolygon(p, n, vec4(0.0, 0.0, -1.0, r.z * (1.0 - 1e-6)));
        if (n < 3) discard;
    }
    tableMask(p, n, r, shift);
    OUTPUTS
}
