#include "visibility/GlBitmaskSampler.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "visibility/Error.h"
#include "visibility/HoughMaskTable.h"
#include "visibility/ShaftGeometry.h"
#include "visibility/gl/GlShaders.h"

namespace sightline {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

constexpr int kMaxTargets = kMaxSourceSamples / 128;

const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in uint aInstance;
out vec3 vWorld;
flat out uint vInstance;
void main() { vWorld = aPosition; vInstance = aInstance; }
)";

// Shared by the geometry and fragment shaders: Sutherland-Hodgman against one plane, keeping
// dot(plane.xyz, X) + plane.w > 0.
const char* kClipFunction = R"(
int clipPolygon(inout vec3 p[8], int n, vec4 plane)
{
    vec3 q[8];
    int m = 0;
    for (int i = 0; i < n; ++i) {
        vec3 a = p[i], b = p[(i + 1) % n];
        float da = dot(plane.xyz, a) + plane.w, db = dot(plane.xyz, b) + plane.w;
        if (da > 0.0) q[m++] = a;
        if ((da > 0.0) != (db > 0.0)) q[m++] = a + (b - a) * (da / (da - db));
    }
    p = q;
    return m;
}
)";

const char* kGeometryShader = R"(
layout(triangles) in;
layout(triangle_strip, max_vertices = 4) out;
in vec3 vWorld[];
flat in uint vInstance[];
uniform usamplerBuffer uCullable;     // per instance: watertight culling (section 7) allowed
uniform int uCulling;
uniform vec3 uSourceWorld[4];         // source corners in world space
uniform vec4 uSrcS, uSrcT, uSrcD;     // world -> source coordinates (s, t, d)
uniform vec4 uRcvS, uRcvT, uRcvD;     // world -> receiver coordinates
uniform float uMarginS, uMarginR, uMinReceiverD;
uniform vec3 uCorner[4];              // source corners in receiver coordinates
uniform ivec2 uReceiverGrid;
flat out vec3 gPoly[7];               // clipped triangle in source coordinates
flat out int gCount;
flat out int gClipPerSample;
#if TABLE_MODE
flat out vec4 gRegion;                // influence region before padding: (lo, hi)
#endif

void main()
{
    // Watertight front-face culling (section 7), as in CpuBitmaskSampler: a front face of a
    // closed mesh, seen from all four source corners, cannot be the only blocker of a segment.
    if (uCulling != 0 && texelFetch(uCullable, int(vInstance[0])).r != 0u) {
        vec3 n = cross(vWorld[1] - vWorld[0], vWorld[2] - vWorld[0]);
        bool front = true;
        for (int c = 0; c < 4; ++c) front = front && dot(n, uSourceWorld[c] - vWorld[0]) > 0.0;
        if (front) return;
    }
    vec3 p[8];
    p[0] = vWorld[0]; p[1] = vWorld[1]; p[2] = vWorld[2];
    int n = clipPolygon(p, 3, uSrcD - vec4(0, 0, 0, uMarginS));
    if (n < 3) return;
    n = clipPolygon(p, n, uRcvD - vec4(0, 0, 0, uMarginR));
    if (n < 3) return;

    // Influence region (section 3): projections from the source corners, as a box.
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    bool whole = false;
    float maxD = -1e30;
    vec3 poly[7];
    for (int i = 0; i < n; ++i) {
        vec4 x = vec4(p[i], 1.0);
        poly[i] = vec3(dot(uSrcS, x), dot(uSrcT, x), dot(uSrcD, x));
        maxD = max(maxD, poly[i].z);
        vec3 r = vec3(dot(uRcvS, x), dot(uRcvT, x), dot(uRcvD, x));
        for (int c = 0; c < 4; ++c) {
            float denominator = uCorner[c].z - r.z;
            if (denominator <= 1e-6 * uCorner[c].z) { whole = true; continue; }
            vec2 y = uCorner[c].xy + (r.xy - uCorner[c].xy) * (uCorner[c].z / denominator);
            lo = min(lo, y);
            hi = max(hi, y);
        }
    }
    vec2 pad = 0.5 / vec2(uReceiverGrid);   // half a sample: boundary samples stay covered
    if (whole) { lo = vec2(0.0); hi = vec2(1.0); }
#if TABLE_MODE
    vec4 region = vec4(lo, hi);
#endif
    lo = clamp(lo - pad, 0.0, 1.0);
    hi = clamp(hi + pad, 0.0, 1.0);
    if (any(greaterThanEqual(lo, hi))) return;

    int clipPerSample = maxD >= uMinReceiverD * (1.0 - 1e-6) ? 1 : 0;
    vec2 corners[4] = vec2[4](vec2(lo.x, lo.y), vec2(hi.x, lo.y), vec2(lo.x, hi.y), vec2(hi.x, hi.y));
    for (int k = 0; k < 4; ++k) {
        for (int i = 0; i < 7; ++i) gPoly[i] = i < n ? poly[i] : vec3(0.0);
        gCount = n;
        gClipPerSample = clipPerSample;
#if TABLE_MODE
        gRegion = region;
#endif
        gl_Position = vec4(corners[k] * 2.0 - 1.0, 0.0, 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
)";

const char* kFragmentShader = R"(
flat in vec3 gPoly[7];
flat in int gCount;
flat in int gClipPerSample;
#if TABLE_MODE
flat in vec4 gRegion;
#endif
uniform vec3 uR0, uRU, uRV;           // receiver (s', t') -> source coordinates
uniform ivec2 uSourceGrid, uReceiverGrid;
uniform uint uJitterSeed;             // decorrelated sampling (section 6.2); 0: off

uint mask[4 * TARGETS];

// The same offsets as SourceJitter.h (lowbias32 hash, 2^-24 grid: exact in float).
uint mixBits(uint x)
{
    x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
    return x;
}
vec2 jitterOffset(int j)
{
    if (uJitterSeed == 0u) return vec2(0.0);
    uint h1 = mixBits(uJitterSeed ^ mixBits(uint(j) + 0x9e3779b9u));
    uint h2 = mixBits(h1 + 0x85ebca6bu);
    return vec2(float(h1 >> 8), float(h2 >> 8)) * (1.0 / 16777216.0) - 0.5;
}

void setRange(int first, int last)
{
    for (int w = first >> 5; w <= (last >> 5); ++w) {
        int a = max(first, w * 32) - w * 32, b = min(last, w * 32 + 31) - w * 32;
        uint bits = (b == 31 ? 0xffffffffu : ((1u << (b + 1)) - 1u)) & ~((1u << a) - 1u);
        mask[w] |= bits;
    }
}

// Samples k at (k + 0.5) / n inside [lo, hi], as an index range (empty when first > last).
ivec2 sampleRange(float lo, float hi, int n)
{
    float x0 = clamp(lo * float(n) - 0.5, -2.0, float(n) + 1.0);
    float x1 = clamp(hi * float(n) - 0.5, -2.0, float(n) + 1.0);
    return ivec2(max(0, int(ceil(x0))), min(n - 1, int(floor(x1))));
}

#if TABLE_MODE
// Table mode (section 5): the Hough table of HoughMaskTable, texel (i, k) at buffer texels
// (k * width + i) * TARGETS + target, each 128 source bits in the render targets' order.
uniform usamplerBuffer uTable;
uniform ivec2 uTableSize;             // (angles, distances)
const float kPi = 3.14159265358979;
const float kMaxDistance = 0.70710678118654752;   // sqrt(2) / 2

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

// CpuBitmaskSampler's tableMask: the AND of the masks of the backprojection's edges, inside on
// the left of each. Each edge's line on the source plane (d = 0) comes from the plane through r
// and the 3D edge, N = (p_k - r) x (p_i - r): the line is N.xy . X = N . r and the left normal of
// the backprojected edge from p_k to p_i is -N.xy. Projecting the end points instead loses all
// precision in float when a vertex lies just short of r's distance (see the exact mode below).
// The CPU takes the edges counter-clockwise by the sign of the projected area; central
// projection from r keeps orientation, so that sign is the polygon's orientation seen from r,
// found once for all edges (per-edge tests flip independently on slivers seen edge-on). Zero:
// seen edge-on, no inside (the CPU's zero-area rule).
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
        // Signed distance from the centre of the source grid as this receiver sample sees it.
        float dist = -dot(normal, r) / length2 - dot(left, vec2(0.5) + shift);
        andTexel(left, dist);
        anyEdge = true;
    }
    if (!anyEdge)
        for (int w = 0; w < 4 * TARGETS; ++w) mask[w] = 0u;
}
#endif

void main()
{
    vec2 sr = gl_FragCoord.xy / vec2(uReceiverGrid);
#if TABLE_MODE
    // The CPU sampler's influence region, unpadded: in table mode a backprojection that misses
    // every sample can still pick up samples from a nearest texel, so the pairs evaluated must
    // be the same as on the CPU for the answers to agree (without this, a third more rays
    // differ from the CPU's table mode on the random scenes of tst_GlBitmaskSampler).
    if (any(lessThan(sr, gRegion.xy)) || any(greaterThan(sr, gRegion.zw))) discard;
#endif
    vec3 r = uR0 + sr.x * uRU + sr.y * uRV;
    vec3 p[8];
    int n = gCount;
    for (int i = 0; i < 7; ++i) p[i] = gPoly[i];
    if (gClipPerSample != 0) {   // points at or beyond this sample's distance lie on none of its rays
        n = clipPolygon(p, n, vec4(0.0, 0.0, -1.0, r.z * (1.0 - 1e-6)));
        if (n < 3) discard;
    }
#if TABLE_MODE
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    tableMask(p, n, r, jitterOffset(pixel.y * uReceiverGrid.x + pixel.x) / vec2(uSourceGrid));
#else
    // Backprojection onto the source (section 4).
    float ps[8], pt[8];
    float tMin = 1e30, tMax = -1e30;
    for (int i = 0; i < n; ++i) {
        float k = r.z / (r.z - p[i].z);
        ps[i] = r.x + (p[i].x - r.x) * k;
        pt[i] = r.y + (p[i].y - r.y) * k;
        tMin = min(tMin, pt[i]);
        tMax = max(tMax, pt[i]);
    }
    // With jitter, this receiver sample's source samples sit at the grid positions plus shift.
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec2 shift = jitterOffset(pixel.y * uReceiverGrid.x + pixel.x) / vec2(uSourceGrid);
    ivec2 rows = sampleRange(tMin - shift.y, tMax - shift.y, uSourceGrid.y);
    if (rows.x > rows.y) discard;
    for (int w = 0; w < 4 * TARGETS; ++w) mask[w] = 0u;
    // Exact set (section 5, without the Hough table): per source row, the interval of columns.
    // The points that backproject onto row line t = tb form a plane through r, linear in X:
    //     (x.t - r.t) r.d - (tb - r.t) (r.d - x.d) = 0,
    // so each edge is cut by that plane in 3D and only the cut point is projected. Interpolating
    // between projected vertices instead loses all precision in float when a vertex lies just
    // short of r's distance (it projects ~10^6 times farther out).
    for (int b = rows.x; b <= rows.y; ++b) {
        float tb = (float(b) + 0.5) / float(uSourceGrid.y) + shift.y;
        float lo = 1e30, hi = -1e30;
        for (int i = 0, k = n - 1; i < n; k = i++) {
            float fk = (p[k].y - r.y) * r.z - (tb - r.y) * (r.z - p[k].z);
            float fi = (p[i].y - r.y) * r.z - (tb - r.y) * (r.z - p[i].z);
            if (fk * fi > 0.0) continue;
            if (fk == fi) { lo = min(lo, min(ps[k], ps[i])); hi = max(hi, max(ps[k], ps[i])); continue; }
            vec3 x = p[k] + (p[i] - p[k]) * (fk / (fk - fi));
            float s = r.x + (x.x - r.x) * (r.z / (r.z - x.z));
            lo = min(lo, s);
            hi = max(hi, s);
        }
        ivec2 columns = sampleRange(lo - shift.x, hi - shift.x, uSourceGrid.x);
        if (columns.x <= columns.y)
            setRange(b * uSourceGrid.x + columns.x, b * uSourceGrid.x + columns.y);
    }
#endif
    OUTPUTS
}
)";

/// "#version" and the compile-time switches shared by the geometry and fragment shaders.
std::string preamble(int targets, MaskMode mode)
{
    return "#version 450 core\n#define TARGETS " + std::to_string(targets) + "\n#define TABLE_MODE " +
           (mode == MaskMode::Table ? "1" : "0") + "\n";
}

std::string fragmentSource(int targets, MaskMode mode)
{
    std::string declarations, outputs;
    for (int k = 0; k < targets; ++k) {
        const std::string n = std::to_string(k), w = std::to_string(4 * k);
        declarations.append("layout(location = ").append(n).append(") out uvec4 o").append(n).append(";\n");
        // o<k> = uvec4(mask[4k + 0 .. 4k + 3])
        outputs.append("o").append(n).append(" = uvec4(mask[").append(w).append("], mask[").append(w)
            .append(" + 1], mask[").append(w).append(" + 2], mask[").append(w).append(" + 3]);\n    ");
    }
    std::string body = kFragmentShader;
    body.replace(body.find("OUTPUTS"), 7, outputs);
    return preamble(targets, mode) + declarations + kClipFunction + body;
}

glm::vec4 affineRow(const glm::dvec3& axis, const glm::dvec3& origin)
{
    return glm::vec4(glm::vec3(axis), float(-glm::dot(axis, origin)));
}

/// The Hough table's masks as 32-bit words, `targets` RGBA32UI texels per entry: source bit b in
/// word b / 32, bit b % 32, the render targets' layout (DESIGN.md §2: bit index b*na + a).
std::vector<std::uint32_t> packTable(const HoughMaskTable& table, int targets)
{
    const std::size_t wordsPerEntry = std::size_t(targets) * 4;
    std::vector<std::uint32_t> words(std::size_t(table.width()) * std::size_t(table.height()) * wordsPerEntry, 0);
    for (int k = 0; k < table.height(); ++k)
        for (int i = 0; i < table.width(); ++i) {
            const std::uint64_t* mask = table.texel(i, k);
            std::uint32_t* out = &words[(std::size_t(k) * std::size_t(table.width()) + std::size_t(i)) * wordsPerEntry];
            for (int w = 0; w < table.wordsPerMask(); ++w) {
                out[2 * w] = std::uint32_t(mask[w]);
                out[2 * w + 1] = std::uint32_t(mask[w] >> 32);
            }
        }
    return words;
}

} // namespace

struct GlBitmaskSampler::Impl {
    const gl::Functions& gl;
    GLuint programs[2][kMaxTargets + 1] = {};   // by mask mode and target count, compiled on first use
    GLuint vertexArray = 0, buffer = 0, instanceBuffer = 0;
    GLsizei vertexCount = 0;
    GLuint cullableBuffer = 0, cullableTexture = 0;   // per instance, uploaded per call
    struct InstanceInfo {
        bool watertight = false;
        Bounds bounds;
    };
    std::vector<InstanceInfo> instances;   // empty for a bare triangle soup
    GLuint framebuffer = 0;
    GLuint textures[kMaxTargets] = {};
    int targetCount = 0, width = 0, height = 0;
    /// Table mode: the Hough table of the last source grid and resolution, as a buffer texture
    /// (RGBA32UI texels; a buffer holds the 8-texel entries of an 8192x8192 table where a 2D
    /// texture's side would not). The editor samples one grid many times: built once.
    struct TableKey {
        int na = 0, nb = 0, width = 0, height = 0;
        bool operator==(const TableKey&) const = default;
    };
    TableKey tableKey;
    GLuint tableBuffer = 0, tableTexture = 0;

    explicit Impl(const gl::Functions& functions) : gl(functions) {}

    ~Impl()
    {
        for (const auto& byTargets : programs)
            for (GLuint program : byTargets)
                if (program)
                    gl.DeleteProgram(program);
        releaseTargets();
        gl.DeleteTextures(1, &tableTexture);
        gl.DeleteBuffers(1, &tableBuffer);
        gl.DeleteTextures(1, &cullableTexture);
        gl.DeleteBuffers(1, &cullableBuffer);
        gl.DeleteBuffers(1, &instanceBuffer);
        gl.DeleteBuffers(1, &buffer);
        gl.DeleteVertexArrays(1, &vertexArray);
    }

    GLuint program(int targets, MaskMode mode)
    {
        GLuint& slot = programs[mode == MaskMode::Table ? 1 : 0][targets];
        if (slot)
            return slot;
        return slot = gl::buildProgram(gl,
                                       {{GL_VERTEX_SHADER, kVertexShader},
                                        {GL_GEOMETRY_SHADER, preamble(targets, mode) + kClipFunction + kGeometryShader},
                                        {GL_FRAGMENT_SHADER, fragmentSource(targets, mode)}},
                                       "GL bitmask sampler");
    }

    /// Builds (on the CPU, HoughMaskTable) and uploads the table for this grid and resolution
    /// unless it is the one already uploaded. Returns the milliseconds spent (0 when cached).
    double ensureTable(int na, int nb, int tableWidth, int tableHeight)
    {
        const TableKey key{na, nb, tableWidth, tableHeight};
        if (tableTexture && key == tableKey)
            return 0.0;
        const auto start = Clock::now();
        const int targets = (na * nb + 127) / 128;
        GLint maxTexels = 0;
        gl.GetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
        const double texels = double(tableWidth) * double(tableHeight) * double(targets);
        if (texels > double(maxTexels))
            throw Error("GL bitmask sampler: a " + std::to_string(tableWidth) + "x" + std::to_string(tableHeight) +
                        " Hough table for " + std::to_string(na * nb) + " source samples needs " +
                        std::to_string(std::uint64_t(texels)) + " texels, the context allows " + std::to_string(maxTexels));
        const std::vector<std::uint32_t> words = packTable(HoughMaskTable(na, nb, tableWidth, tableHeight), targets);
        if (!tableBuffer) {
            gl.CreateBuffers(1, &tableBuffer);
            gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &tableTexture);
        }
        tableKey = {};   // until the upload succeeded
        gl.NamedBufferData(tableBuffer, GLsizeiptr(words.size() * sizeof(std::uint32_t)), words.data(), GL_STATIC_DRAW);
        gl.TextureBuffer(tableTexture, GL_RGBA32UI, tableBuffer);
        if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
            throw Error("GL bitmask sampler: uploading the " + std::to_string(tableWidth) + "x" +
                        std::to_string(tableHeight) + " Hough table failed (OpenGL error " + std::to_string(error) + ")");
        tableKey = key;
        return msSince(start);
    }

    void releaseTargets()
    {
        if (framebuffer)
            gl.DeleteFramebuffers(1, &framebuffer);
        if (targetCount)
            gl.DeleteTextures(targetCount, textures);
        framebuffer = 0;
        targetCount = 0;
    }

    void ensureTargets(int targets, int w, int h)
    {
        if (targets == targetCount && w == width && h == height)
            return;
        releaseTargets();
        gl.CreateFramebuffers(1, &framebuffer);
        gl.CreateTextures(GL_TEXTURE_2D, targets, textures);
        GLenum buffers[kMaxTargets];
        for (int k = 0; k < targets; ++k) {
            gl.TextureStorage2D(textures[k], 1, GL_RGBA32UI, w, h);
            gl.NamedFramebufferTexture(framebuffer, GLenum(GL_COLOR_ATTACHMENT0 + k), textures[k], 0);
            buffers[k] = GLenum(GL_COLOR_ATTACHMENT0 + k);
        }
        gl.NamedFramebufferDrawBuffers(framebuffer, targets, buffers);
        if (gl.CheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw Error("GL bitmask sampler: incomplete framebuffer for " + std::to_string(targets) +
                        " RGBA32UI targets of " + std::to_string(w) + "x" + std::to_string(h));
        targetCount = targets;
        width = w;
        height = h;
    }
};

GlBitmaskSampler::GlBitmaskSampler(const gl::Functions& gl, const Scene& scene)
    : GlBitmaskSampler(gl, worldTriangles(scene))
{
    for (const Instance& instance : scene.instances)
        impl_->instances.push_back({scene.meshes[instance.mesh].watertight, scene.instanceBounds(instance)});
}

GlBitmaskSampler::GlBitmaskSampler(const gl::Functions& gl, const WorldTriangles& triangles)
    : impl_(std::make_unique<Impl>(gl))
{
    GLint drawBuffers = 0;
    gl.GetIntegerv(GL_MAX_DRAW_BUFFERS, &drawBuffers);
    if (drawBuffers < kMaxTargets)
        throw Error("GL bitmask sampler: needs 8 draw buffers, the context has " + std::to_string(drawBuffers));
    gl.CreateVertexArrays(1, &impl_->vertexArray);
    gl.CreateBuffers(1, &impl_->buffer);
    gl.NamedBufferData(impl_->buffer, GLsizeiptr(triangles.vertices.size() * sizeof(glm::vec3)),
                       triangles.vertices.data(), GL_STATIC_DRAW);
    gl.VertexArrayVertexBuffer(impl_->vertexArray, 0, impl_->buffer, 0, sizeof(glm::vec3));
    gl.VertexArrayAttribFormat(impl_->vertexArray, 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl.VertexArrayAttribBinding(impl_->vertexArray, 0, 0);
    gl.EnableVertexArrayAttrib(impl_->vertexArray, 0);
    // Each vertex carries its triangle's instance, for watertight culling.
    std::vector<std::uint32_t> instanceOfVertex(triangles.vertices.size());
    for (std::size_t v = 0; v < instanceOfVertex.size(); ++v)
        instanceOfVertex[v] = v / 3 < triangles.instanceOf.size() ? triangles.instanceOf[v / 3] : 0u;
    gl.CreateBuffers(1, &impl_->instanceBuffer);
    gl.NamedBufferData(impl_->instanceBuffer, GLsizeiptr(instanceOfVertex.size() * sizeof(std::uint32_t)),
                       instanceOfVertex.data(), GL_STATIC_DRAW);
    gl.VertexArrayVertexBuffer(impl_->vertexArray, 1, impl_->instanceBuffer, 0, sizeof(std::uint32_t));
    gl.VertexArrayAttribIFormat(impl_->vertexArray, 1, 1, GL_UNSIGNED_INT, 0);
    gl.VertexArrayAttribBinding(impl_->vertexArray, 1, 1);
    gl.EnableVertexArrayAttrib(impl_->vertexArray, 1);
    gl.CreateBuffers(1, &impl_->cullableBuffer);
    gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &impl_->cullableTexture);
    impl_->vertexCount = GLsizei(triangles.vertices.size());
    impl_->program(1, MaskMode::Exact);   // compile now: shader errors surface at construction
}

GlBitmaskSampler::~GlBitmaskSampler() = default;

HiddenSampleMap GlBitmaskSampler::sample(const Patch& source, const Patch& receiver, GlBitmaskStats* stats)
{
    return sample(source, receiver, GlBitmaskOptions{}, stats);
}

HiddenSampleMap GlBitmaskSampler::sample(const Patch& source, const Patch& receiver, const GlBitmaskOptions& options,
                                         GlBitmaskStats* stats)
{
    const SourceJitter& jitter = options.jitter;
    validatePatchPair(source, receiver);
    const bool tableMode = options.mode == MaskMode::Table;
    if (tableMode)
        HoughMaskTable::checkResolution(options.tableWidth, options.tableHeight);
    const gl::Functions& gl = impl_->gl;
    const auto setupStart = Clock::now();
    const int targets = (source.sampleCount() + 127) / 128;
    const GLuint program = impl_->program(targets, options.mode);
    impl_->ensureTargets(targets, receiver.na, receiver.nb);
    double tableMs = 0.0;
    if (tableMode) {
        // Section 5: the bitmask texture, on texture unit 1 (unit 0 holds the culling flags).
        tableMs = impl_->ensureTable(source.na, source.nb, options.tableWidth, options.tableHeight);
        gl.BindTextureUnit(1, impl_->tableTexture);
        gl.ProgramUniform1i(program, gl.GetUniformLocation(program, "uTable"), 1);
        gl.ProgramUniform2i(program, gl.GetUniformLocation(program, "uTableSize"), options.tableWidth, options.tableHeight);
    }

    const ShaftFrames frames(source, receiver);
    auto set4 = [&](const char* name, const glm::vec4& v) { gl.ProgramUniform4fv(program, gl.GetUniformLocation(program, name), 1, &v.x); };
    auto set3 = [&](const char* name, const glm::vec3& v) { gl.ProgramUniform3fv(program, gl.GetUniformLocation(program, name), 1, &v.x); };
    auto set1 = [&](const char* name, double v) { gl.ProgramUniform1f(program, gl.GetUniformLocation(program, name), float(v)); };
    auto set2i = [&](const char* name, int a, int b) { gl.ProgramUniform2i(program, gl.GetUniformLocation(program, name), a, b); };
    set4("uSrcS", affineRow(frames.source.sAxis, frames.source.origin));
    set4("uSrcT", affineRow(frames.source.tAxis, frames.source.origin));
    set4("uSrcD", affineRow(frames.source.dAxis, frames.source.origin));
    set4("uRcvS", affineRow(frames.receiver.sAxis, frames.receiver.origin));
    set4("uRcvT", affineRow(frames.receiver.tAxis, frames.receiver.origin));
    set4("uRcvD", affineRow(frames.receiver.dAxis, frames.receiver.origin));
    set1("uMarginS", frames.sourceMargin);
    set1("uMarginR", frames.receiverMargin);
    double minReceiverD = 1e300;
    std::array<glm::vec3, 4> corners;
    for (int k = 0; k < 4; ++k) {
        const glm::dvec3 sc = source.corner + double(k & 1) * source.u + double(k >> 1) * source.v;
        corners[std::size_t(k)] = glm::vec3(frames.receiver.coordinates(sc));
        const glm::dvec3 rc = receiver.corner + double(k & 1) * receiver.u + double(k >> 1) * receiver.v;
        minReceiverD = std::min(minReceiverD, frames.source.coordinates(rc).z);
    }
    set1("uMinReceiverD", minReceiverD);
    gl.ProgramUniform3fv(program, gl.GetUniformLocation(program, "uCorner"), 4, &corners[0].x);
    // Receiver (s', t') -> source coordinates: affine, so origin plus two edge images.
    const glm::dvec3 r0 = frames.source.coordinates(receiver.corner);
    set3("uR0", glm::vec3(r0));
    set3("uRU", glm::vec3(frames.source.coordinates(receiver.corner + receiver.u) - r0));
    set3("uRV", glm::vec3(frames.source.coordinates(receiver.corner + receiver.v) - r0));
    set2i("uSourceGrid", source.na, source.nb);
    set2i("uReceiverGrid", receiver.na, receiver.nb);
    gl.ProgramUniform1ui(program, gl.GetUniformLocation(program, "uJitterSeed"), jitter.seed);

    // Watertight culling: which instances may drop their front faces for this receiver.
    std::vector<std::uint8_t> cullable(std::max<std::size_t>(1, impl_->instances.size()), 0);
    bool culling = false;
    if (options.watertightCulling)
        for (std::size_t i = 0; i < impl_->instances.size(); ++i) {
            cullable[i] = impl_->instances[i].watertight && receiverApartFrom(impl_->instances[i].bounds, receiver);
            culling = culling || cullable[i];
        }
    gl.NamedBufferData(impl_->cullableBuffer, GLsizeiptr(cullable.size()), cullable.data(), GL_STREAM_DRAW);
    gl.TextureBuffer(impl_->cullableTexture, GL_R8UI, impl_->cullableBuffer);
    gl.BindTextureUnit(0, impl_->cullableTexture);
    gl.ProgramUniform1i(program, gl.GetUniformLocation(program, "uCullable"), 0);
    gl.ProgramUniform1i(program, gl.GetUniformLocation(program, "uCulling"), culling ? 1 : 0);
    std::array<glm::vec3, 4> sourceWorld;
    for (int k = 0; k < 4; ++k)
        sourceWorld[std::size_t(k)] = glm::vec3(source.corner + double(k & 1) * source.u + double(k >> 1) * source.v);
    gl.ProgramUniform3fv(program, gl.GetUniformLocation(program, "uSourceWorld"), 4, &sourceWorld[0].x);

    const GLuint zero[4] = {0, 0, 0, 0};
    for (int k = 0; k < targets; ++k)
        gl.ClearNamedFramebufferuiv(impl_->framebuffer, GL_COLOR, k, zero);
    const double setupMs = msSince(setupStart);

    const auto drawStart = Clock::now();
    gl.BindFramebuffer(GL_FRAMEBUFFER, impl_->framebuffer);
    gl.Viewport(0, 0, receiver.na, receiver.nb);
    gl.Enable(GL_COLOR_LOGIC_OP);
    gl.LogicOp(GL_OR);   // section 5.1: the union over triangles, done by the blending stage
    gl.UseProgram(program);
    gl.BindVertexArray(impl_->vertexArray);
    if (impl_->vertexCount)
        gl.DrawArrays(GL_TRIANGLES, 0, impl_->vertexCount);
    gl.Finish();
    gl.Disable(GL_COLOR_LOGIC_OP);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    const double drawMs = msSince(drawStart);

    const auto readStart = Clock::now();
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    std::vector<std::uint32_t> pixels(std::size_t(receiver.na) * std::size_t(receiver.nb) * 4);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    const int rowBytes = (source.sampleCount() + 7) / 8;
    for (int k = 0; k < targets; ++k) {
        gl.GetTextureImage(impl_->textures[k], 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                           GLsizei(pixels.size() * sizeof(std::uint32_t)), pixels.data());
        // Target k holds source bits [128k, 128k + 128) of every receiver sample, little-endian
        // 32-bit words: the same byte layout as the map's rows.
        const int bytes = std::min(16, rowBytes - 16 * k);
        for (int j = 0; j < map.receiverCount(); ++j)
            std::memcpy(reinterpret_cast<unsigned char*>(map.row(j).data()) + 16 * k, &pixels[std::size_t(j) * 4],
                        std::size_t(bytes));
    }
    if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
        throw Error("GL bitmask sampler: OpenGL error " + std::to_string(error));
    if (stats)
        *stats = {setupMs - tableMs, drawMs, msSince(readStart), tableMs};
    return map;
}

} // namespace sightline
