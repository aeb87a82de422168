#include "editor/ViewportRenderer.h"

#include "editor/LightObjects.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "editor/LevelRelight.h"
#include "editor/RayLayer.h"
#include "visibility/SourceJitter.h"
#include "visibility/gl/GlShaders.h"
#include "glsl/level_shading.glsl.h"
#include "glsl/view_line.frag.h"
#include "glsl/view_line.vert.h"
#include "glsl/view_mesh.frag.h"
#include "glsl/view_mesh.vert.h"
#include "glsl/view_overlay.frag.h"
#include "glsl/view_overlay.vert.h"
#include "glsl/view_rays.vert.h"

namespace sightline::ui {

namespace {

const std::string kMeshFragment = std::string("#version 450 core\n") + glsl::level_shading_glsl + glsl::view_mesh_frag;

} // namespace

struct MeshVertex {
    glm::vec3 position;
    glm::vec3 normal;
    std::uint32_t object;
    glm::vec2 aoUv{-1.0f, -1.0f};
};

namespace {

struct LineVertex {
    glm::vec3 position;
    glm::vec4 colour;
};

std::vector<MeshVertex> meshVertices(const WorldTriangles& triangles, const std::vector<std::size_t>* objectOf)
{
    std::vector<MeshVertex> vertices(triangles.vertices.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::vec3* p = &triangles.vertices[3 * t];
        const glm::vec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
        const float len = glm::length(n);
        const glm::vec3 unit = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
        const std::uint32_t instance = triangles.instanceOf[t];
        const auto object = std::uint32_t(objectOf ? (*objectOf)[instance] : instance);
        for (int k = 0; k < 3; ++k)
            vertices[3 * t + std::size_t(k)] = {p[k], unit, object, {-1.0f, -1.0f}};
    }
    return vertices;
}

/// The gizmo's handles as triangles (one-pixel lines were hard to see and to grab):
/// a shaft facing the eye, 4% of the handle's length wide, and a head that says what a drag does:
/// an arrow (move), a ring about the axis (rotate), a box (scale). The hovered handle is white,
/// unlike the rays' yellow.
void appendGizmoHandles(std::vector<LineVertex>& out, const GizmoFrame& g, GizmoMode mode, const Camera& camera,
                        int hovered)
{
    const glm::vec4 axisColours[3] = {{0.95f, 0.25f, 0.25f, 1.0f}, {0.3f, 0.9f, 0.3f, 1.0f}, {0.3f, 0.5f, 1.0f, 1.0f}};
    const auto tri = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::vec4& colour) {
        out.push_back({glm::vec3(a), colour});
        out.push_back({glm::vec3(b), colour});
        out.push_back({glm::vec3(c), colour});
    };
    const auto strip = [&](const glm::dvec3& from, const glm::dvec3& to, double width, const glm::vec4& colour) {
        // Broadside to the viewer: towards the eye, or against the view in orthographic views.
        const glm::dvec3 toViewer = camera.orthographic ? -camera.forward() : camera.eye() - 0.5 * (from + to);
        glm::dvec3 side = glm::cross(to - from, toViewer);
        const double n = glm::length(side);
        if (!(n > 0.0))
            return;
        side *= 0.5 * width / n;
        tri(from - side, to - side, to + side, colour);
        tri(from - side, to + side, from + side, colour);
    };
    constexpr int kSegments = 16;
    for (int a = 0; a < 3; ++a) {
        const glm::vec4 colour = a == hovered ? glm::vec4(1.0f) : axisColours[a];
        const glm::dvec3 axis = g.axes[std::size_t(a)];
        const glm::dvec3 u = g.axes[std::size_t((a + 1) % 3)], v = g.axes[std::size_t((a + 2) % 3)];
        const double L = g.length, w = 0.04 * L;
        const glm::dvec3 tip = g.pivot + L * axis;
        const auto circle = [&](int k, double r) {
            const double t = 2.0 * 3.14159265358979323846 * k / kSegments;
            return r * (std::cos(t) * u + std::sin(t) * v);
        };
        switch (mode) {
        case GizmoMode::Move: {
            strip(g.pivot, tip - 0.2 * L * axis, w, colour);
            const glm::dvec3 base = tip - 0.22 * L * axis;   // a cone
            for (int k = 0; k < kSegments; ++k)
                tri(base + circle(k, 0.08 * L), base + circle(k + 1, 0.08 * L), tip, colour);
            break;
        }
        case GizmoMode::Rotate: {
            strip(g.pivot, tip - 0.15 * L * axis, w, colour);
            const glm::dvec3 centre = tip - 0.15 * L * axis;   // a ring about the axis
            for (int k = 0; k < kSegments; ++k)
                strip(centre + circle(k, 0.15 * L), centre + circle(k + 1, 0.15 * L), w, colour);
            break;
        }
        case GizmoMode::Scale: {
            strip(g.pivot, tip - 0.08 * L * axis, w, colour);
            const glm::dvec3 c = tip - 0.08 * L * axis, e = 0.08 * L * axis, p = 0.08 * L * u, q = 0.08 * L * v;
            const glm::dvec3 faces[6][3] = {{e, p, q}, {-e, q, p}, {p, q, e}, {-p, e, q}, {q, e, p}, {-q, p, e}};
            for (const auto& face : faces) {   // a box: each face as two triangles
                const glm::dvec3 m = c + face[0];
                tri(m - face[1] - face[2], m + face[1] - face[2], m + face[1] + face[2], colour);
                tri(m - face[1] - face[2], m + face[1] + face[2], m - face[1] + face[2], colour);
            }
            break;
        }
        }
    }
}

/// The section cut's handle: a flat grip on the cut plane with an arrow up and an arrow down,
/// white while hovered.
void appendCutHandle(std::vector<LineVertex>& out, const CutHandle& h, const Camera& camera, bool hovered)
{
    const glm::vec4 colour = hovered ? glm::vec4(1.0f) : glm::vec4(kCutColour, 1.0f);
    const auto tri = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
        out.push_back({glm::vec3(a), colour});
        out.push_back({glm::vec3(b), colour});
        out.push_back({glm::vec3(c), colour});
    };
    const glm::dvec3 up(0.0, 1.0, 0.0);
    const double s = h.size;
    // Across the view: the arrows' shafts and heads face the viewer whatever the orbit.
    glm::dvec3 across = glm::cross(up, camera.orthographic ? -camera.forward() : camera.eye() - h.point);
    across = glm::length(across) > 1e-12 ? glm::normalize(across) : camera.right();
    const glm::dvec3 depth = glm::cross(across, up);
    constexpr int kSegments = 16;
    for (double sign : {1.0, -1.0}) {
        const glm::dvec3 base = h.point + sign * 0.55 * s * up, tip = h.point + sign * s * up;
        const glm::dvec3 w = 0.035 * s * across;
        tri(h.point - w, base - w, base + w);   // the shaft
        tri(h.point - w, base + w, h.point + w);
        for (int k = 0; k < kSegments; ++k) {   // a cone
            const double a0 = 2.0 * 3.14159265358979323846 * k / kSegments, a1 = 2.0 * 3.14159265358979323846 * (k + 1) / kSegments;
            const glm::dvec3 r0 = 0.16 * s * (std::cos(a0) * across + std::sin(a0) * depth);
            const glm::dvec3 r1 = 0.16 * s * (std::cos(a1) * across + std::sin(a1) * depth);
            tri(base + r0, base + r1, tip);
        }
    }
    // The grip: a flat disc lying in the cut plane.
    for (int k = 0; k < kSegments; ++k) {
        const double a0 = 2.0 * 3.14159265358979323846 * k / kSegments, a1 = 2.0 * 3.14159265358979323846 * (k + 1) / kSegments;
        tri(h.point, h.point + 0.3 * s * (std::cos(a0) * across + std::sin(a0) * depth),
            h.point + 0.3 * s * (std::cos(a1) * across + std::sin(a1) * depth));
    }
}

} // namespace

RaySubset raySubset(int sourceCount, int receiverCount, int cap)
{
    RaySubset s;
    const auto S = std::uint64_t(std::max(sourceCount, 0)), R = std::uint64_t(std::max(receiverCount, 0));
    const auto limit = std::uint64_t(std::max(cap, 1));
    if (S == 0 || R == 0)
        return s;
    if (S * R <= limit) {
        s.receivers = std::uint32_t(R);
        s.sourcePerReceiver = std::uint32_t(S);
        return s;
    }
    s.sourcePerReceiver = std::uint32_t(std::clamp<std::uint64_t>(limit / R, 1, S));
    s.sourceStride = std::uint32_t(S / s.sourcePerReceiver);
    s.receivers = std::uint32_t(std::min<std::uint64_t>(R, limit / s.sourcePerReceiver));
    s.receiverStride = std::uint32_t(R / s.receivers);
    return s;
}

std::pair<std::uint32_t, std::uint32_t> subsetRay(const RaySubset& s, std::uint32_t k)
{
    const std::uint32_t jk = k % s.receivers, ik = k / s.receivers;
    const std::uint32_t j = jk * s.receiverStride + (s.receiverStride > 1 ? mixBits(jk) % s.receiverStride : 0);
    const std::uint32_t i = ik * s.sourceStride + (s.sourceStride > 1 ? mixBits(j ^ 0x5bd1e995U) % s.sourceStride : 0);
    return {j, i};
}

std::vector<std::uint32_t> freeDrawnRays(const HiddenSampleMap& map, const RaySubset& subset)
{
    std::vector<std::uint32_t> free;
    const auto count = std::uint32_t(subset.count());
    free.reserve(count);
    for (std::uint32_t k = 0; k < count; ++k) {
        const auto [j, i] = subsetRay(subset, k);
        if (!map.blocked(int(j), int(i)))
            free.push_back(k);
    }
    return free;
}

std::vector<std::uint32_t> disagreementDrawnRays(const RayDisagreement& d, std::uint32_t cap)
{
    const std::uint64_t total = d.falseBlockedCount + d.falseFreeCount + d.tieCount;
    const std::uint64_t stride = cap == 0 ? total + 1 : std::max<std::uint64_t>(1, (total + cap - 1) / cap);
    const auto receivers = std::uint32_t(d.falseBlocked.receiverCount());
    std::vector<std::uint32_t> list;
    list.reserve(std::size_t(std::min<std::uint64_t>(total, cap)));
    std::uint64_t seen = 0;
    const std::pair<const HiddenSampleMap*, std::uint32_t> kinds[] = {{&d.falseBlocked, 1u}, {&d.falseFree, 2u}, {&d.ties, 3u}};
    for (const auto& [map, kind] : kinds)
        for (std::uint32_t j = 0; j < receivers; ++j) {
            const auto row = map->row(int(j));
            for (std::size_t w = 0; w < row.size(); ++w)
                for (std::uint64_t bits = row[w]; bits; bits &= bits - 1, ++seen)
                    if (seen % stride == 0) {
                        const auto i = std::uint32_t(64 * w) + std::uint32_t(std::countr_zero(bits));
                        list.push_back((i * receivers + j) | kind << 30);
                    }
        }
    return list;
}

std::vector<std::uint32_t> blockedDrawnRays(const HiddenSampleMap& map, const RaySubset& subset)
{
    const auto count = std::uint32_t(subset.count());
    std::vector<std::uint32_t> bits((std::size_t(count) + 31) / 32, 0u);
    for (std::uint32_t k = 0; k < count; ++k) {
        const auto [j, i] = subsetRay(subset, k);
        if (map.blocked(int(j), int(i)))
            bits[k >> 5] |= 1u << (k & 31u);
    }
    return bits;
}

Cutaway cutaway(const ViewStyle& style, const Camera& camera)
{
    if (!style.cutaway)
        return {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    // Never from what is edited, so that dragging a patch or an occluder never moves the cut (and
    // the cached background stays valid): the style's own height, and the nearer half of the way
    // to the orbit target.
    const double height = std::isnan(style.cutHeight) ? camera.target.y + 1.5 : style.cutHeight;
    return {height, 0.5 * camera.distance};
}

Cutaway cutaway(const FrameState& f) { return cutaway(f.style, f.camera); }

bool hiddenByCut(const Cutaway& cut, const Camera& camera, const glm::dvec3& point)
{
    return point.y > cut.height || glm::dot(point - camera.eye(), camera.forward()) < cut.depth;
}

bool RenderTarget::create(const gl::Functions& gl, int w, int h)
{
    destroy(gl);
    gl.CreateFramebuffers(1, &framebuffer);
    gl.CreateRenderbuffers(1, &colour);
    gl.NamedRenderbufferStorage(colour, GL_RGBA8, w, h);
    gl.CreateRenderbuffers(1, &depth);
    gl.NamedRenderbufferStorage(depth, GL_DEPTH24_STENCIL8, w, h);
    gl.NamedFramebufferRenderbuffer(framebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
    gl.NamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth);
    width = w;
    height = h;
    return gl.CheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

void RenderTarget::destroy(const gl::Functions& gl)
{
    if (!framebuffer)
        return;
    gl.DeleteFramebuffers(1, &framebuffer);
    gl.DeleteRenderbuffers(1, &colour);
    gl.DeleteRenderbuffers(1, &depth);
    *this = {};
}

struct ViewportRenderer::MeshBuffer {
    GLuint vao = 0, vbo = 0;
    GLsizei vertices = 0;
    GLuint hiddenBuffer = 0, hiddenTexture = 0;   ///< per object id, 1 where hidden
    bool anyHidden = false;
};

struct ViewportRenderer::Impl {
    const gl::Functions& gl;
    GLuint meshProgram = 0, lineProgram = 0, rayProgram = 0, overlayProgram = 0;
    MeshBuffer sceneFile, occluders;
    GLuint lineVao = 0, lineVbo = 0;
    GLuint rayVao = 0;
    const HiddenSampleMap* map = nullptr;
    GLuint endsBuffer = 0, endsTexture = 0;
    // The drawn rays (freeDrawnRays, or blockedDrawnRays while blocked ones are shown), for the
    // map, subset and kind they were listed for.
    GLuint raysBuffer = 0, raysTexture = 0;
    GLuint selectedBuffer = 0, selectedTexture = 0;   ///< setSelectedRays, listed as disagreement class 1
    std::vector<std::uint32_t> selected;              ///< entries i * receivers + j | 1 << 30
    int selectedSources = 0, selectedReceivers = 0;
    bool selectedListed = false;
    const HiddenSampleMap* listedMap = nullptr;
    const RayDisagreement* disagreement = nullptr;         ///< setDisagreement
    const RayDisagreement* listedDisagreement = nullptr;   ///< what raysBuffer lists, if a disagreement
    std::uint32_t listedDisagreementCap = 0;
    GLsizei disagreementCount = 0;
    RaySubset listedSubset;
    bool listedFree = false;
    GLsizei freeCount = 0;
    int endsCap = 0;   ///< the subset the uploaded ends are for; 0: none
    GLuint overlayBuffer = 0, overlayTexture = 0;
    ObjectKind overlayPatch = ObjectKind::None;   ///< None: no overlay uploaded
    int overlayNa = 0, overlayNb = 0;
    bool overlaySmooth = false;

    // The scene file's image and depth, kept while the view and the scene file stay the same:
    // during a drag of a patch or an occluder only what moved is drawn again (on a software
    // rasteriser drawing the demo's level costs about fifteen times the blit).
    struct BackgroundKey {
        glm::mat4 viewProj{0.0f};
        int width = 0, height = 0;
        bool wireframe = false;
        float cutHeight = 0.0f, cutDepth = 0.0f;
        int selected = -1;
        std::uint64_t sceneVersion = 0;
        bool ao = false;
        bool lit = false;
        bool pvs = false;
        bool operator==(const BackgroundKey&) const = default;
    };
    RenderTarget cache;
    std::optional<BackgroundKey> cacheKey;
    // A new light map with the same uvs leaves the key as it is: the cache, drawn with the map's
    // surfaces (LevelRelight), is lit again from them instead of drawn again.
    LevelRelight relight;
    std::uint64_t mapVersion = 0;        ///< the light map's texels, uploaded
    std::uint64_t cacheMapVersion = 0;   ///< ... in the cache's colour
    bool cacheRelightable = false;       ///< the cache's surfaces were written under cacheKey
    LevelPass lastPass = LevelPass::Cached;
    // A level's first draw costs llvmpipe about three times its later ones (its memory touched
    // for the first time, not its shaders: a warm-up draw of a small mesh changed nothing). So a
    // newly uploaded level is drawn into the cache over several frames, kFirstDrawChunk vertices
    // each, which keeps the event loop's longest stall on opening a level under 100 ms
    // (StallBenchmark.h); later draws are whole.
    static constexpr GLsizei kFirstDrawChunk = 3 * 24'000;
    // The upload itself (about a third of that budget on the demo's first open) gets a frame of
    // its own.
    GLsizei cacheLevelDrawn = -1;   ///< vertices of the scene file in the cache under cacheKey; -1: not cleared
    bool levelFirstDraw = false;    ///< the scene file was uploaded in chunks and not yet drawn whole
    bool levelJustUploaded = false; ///< ... in this frame: it draws none of it
    bool cacheBroken = false;   ///< the blit failed once (depth formats differ): draw directly
    // The frame is composed here, and only its colour is copied to the caller's framebuffer: on
    // llvmpipe, blitting the cache's depth and stencil into a window's framebuffer takes the
    // shader path (8 stencil passes), about 2/3 of a 1280x720 frame's fixed cost, while blits
    // between targets of the same formats are plain copies.
    RenderTarget compose;
    RayLayer rayLayer;
    std::uint64_t sceneVersion = 0;
    std::vector<MeshVertex> sceneFileVertices;   ///< kept to add the AO map's uvs later
    std::vector<MeshVertex> occluderVertices;    ///< likewise
    GLuint aoTexture = 0;
    int aoWidth = 0, aoHeight = 0;
    bool aoReady = false;   ///< a map and the scene file's uvs are uploaded
    GLuint pvsBuffer = 0, pvsTexture = 0;
    bool pvsReady = false;   ///< culled flags of the scene file's instances are uploaded
    std::vector<std::uint8_t> sceneFileHidden;   ///< the scene file's hidden objects, as uploaded

    void resizeCache(int width, int height)
    {
        if (cache.framebuffer && width == cache.width && height == cache.height)
            return;
        cacheBroken = !cache.create(gl, width, height) || !compose.create(gl, width, height) ||
                      !relight.attach(cache.framebuffer, cache.colour, width, height);
        cacheKey.reset();
    }

    explicit Impl(const gl::Functions& functions) : gl(functions), relight(functions), rayLayer(functions) {}

    GLint loc(GLuint program, const char* name) const { return gl.GetUniformLocation(program, name); }

    void makeMeshBuffer(MeshBuffer& buffer)
    {
        gl.CreateVertexArrays(1, &buffer.vao);
        gl.CreateBuffers(1, &buffer.vbo);
        gl.VertexArrayVertexBuffer(buffer.vao, 0, buffer.vbo, 0, sizeof(MeshVertex));
        gl.EnableVertexArrayAttrib(buffer.vao, 0);
        gl.VertexArrayAttribFormat(buffer.vao, 0, 3, GL_FLOAT, GL_FALSE, offsetof(MeshVertex, position));
        gl.VertexArrayAttribBinding(buffer.vao, 0, 0);
        gl.EnableVertexArrayAttrib(buffer.vao, 1);
        gl.VertexArrayAttribFormat(buffer.vao, 1, 3, GL_FLOAT, GL_FALSE, offsetof(MeshVertex, normal));
        gl.VertexArrayAttribBinding(buffer.vao, 1, 0);
        gl.EnableVertexArrayAttrib(buffer.vao, 2);
        gl.VertexArrayAttribIFormat(buffer.vao, 2, 1, GL_UNSIGNED_INT, offsetof(MeshVertex, object));
        gl.VertexArrayAttribBinding(buffer.vao, 2, 0);
        gl.EnableVertexArrayAttrib(buffer.vao, 3);
        gl.VertexArrayAttribFormat(buffer.vao, 3, 2, GL_FLOAT, GL_FALSE, offsetof(MeshVertex, aoUv));
        gl.VertexArrayAttribBinding(buffer.vao, 3, 0);
    }

    void upload(MeshBuffer& buffer, const std::vector<MeshVertex>& vertices)
    {
        gl.NamedBufferData(buffer.vbo, GLsizeiptr(vertices.size() * sizeof(MeshVertex)), vertices.data(), GL_STATIC_DRAW);
        buffer.vertices = GLsizei(vertices.size());
    }

    void setHidden(MeshBuffer& buffer, const std::vector<std::uint8_t>& hidden)
    {
        buffer.anyHidden = std::find(hidden.begin(), hidden.end(), std::uint8_t(1)) != hidden.end();
        if (!buffer.anyHidden)
            return;
        if (!buffer.hiddenBuffer) {
            gl.CreateBuffers(1, &buffer.hiddenBuffer);
            gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &buffer.hiddenTexture);
        }
        gl.NamedBufferData(buffer.hiddenBuffer, GLsizeiptr(hidden.size()), hidden.data(), GL_STATIC_DRAW);
        gl.TextureBuffer(buffer.hiddenTexture, GL_R8UI, buffer.hiddenBuffer);
    }

    void drawMesh(const MeshBuffer& buffer, const glm::vec3& colour, int selectedObject, const glm::vec4& flat, GLsizei first = 0,
                  GLsizei end = std::numeric_limits<GLsizei>::max())
    {
        end = std::min(end, buffer.vertices);
        if (end <= first)
            return;
        gl.ProgramUniform1i(meshProgram, loc(meshProgram, "hideOn"), buffer.anyHidden ? 1 : 0);
        if (buffer.anyHidden)
            gl.BindTextureUnit(5, buffer.hiddenTexture);
        gl.ProgramUniform3fv(meshProgram, loc(meshProgram, "baseColour"), 1, glm::value_ptr(colour));
        gl.ProgramUniform1i(meshProgram, loc(meshProgram, "selected"), selectedObject);
        gl.ProgramUniform4fv(meshProgram, loc(meshProgram, "flatColour"), 1, glm::value_ptr(flat));
        gl.BindVertexArray(buffer.vao);
        gl.DrawArrays(GL_TRIANGLES, first, end - first);
    }

    /// What every layer of a frame shares.
    struct FrameSetup {
        glm::mat4 viewProj{1.0f};
        Cutaway cut;
        int selectedFile = -1;   ///< the selected object of the scene file, or -1
        bool ao = false;         ///< the AO (or lit) texture is bound and shown
        bool pvs = false;        ///< the PVS tint texture is bound and shown
    };
    // One drawer per layer of ViewportRenderer::render, in drawing order.
    void setCut(double height, double depth);
    void drawLevel(const FrameState& f, const FrameSetup& s, GLuint framebuffer, bool clear, GLsizei first, GLsizei end);
    GLuint composeLevel(const FrameState& f, const FrameSetup& s);
    void drawOccluders(const FrameState& f, int selectedOccluder);
    const Patch* drawOverlay(const FrameState& f, const glm::vec3& eye);
    std::uint64_t drawRays(const FrameState& f, const glm::mat4& viewProj, GLuint target);
    std::uint64_t drawDisagreement(const FrameState& f);
    void drawSelectedRays(const FrameState& f);
    void setListedRayUniforms(const FrameState& f, int sources, int receivers);
    void setRayUniforms(const FrameState& f, const RaySubset& subset);
    void drawGuides(const FrameState& f, const Patch* overlaid, const Cutaway& cut);
};

ViewportRenderer::ViewportRenderer(const gl::Functions& gl) : impl_(std::make_unique<Impl>(gl))
{
    Impl& d = *impl_;
    d.meshProgram = gl::buildProgram(gl, {{GL_VERTEX_SHADER, glsl::view_mesh_vert}, {GL_FRAGMENT_SHADER, kMeshFragment}}, "viewport");
    d.lineProgram = gl::buildProgram(gl, {{GL_VERTEX_SHADER, glsl::view_line_vert}, {GL_FRAGMENT_SHADER, glsl::view_line_frag}}, "viewport");
    d.rayProgram = gl::buildProgram(gl, {{GL_VERTEX_SHADER, glsl::view_rays_vert}, {GL_FRAGMENT_SHADER, glsl::view_line_frag}}, "viewport");
    d.overlayProgram = gl::buildProgram(gl, {{GL_VERTEX_SHADER, glsl::view_overlay_vert}, {GL_FRAGMENT_SHADER, glsl::view_overlay_frag}}, "viewport");
    d.makeMeshBuffer(d.sceneFile);
    d.makeMeshBuffer(d.occluders);

    gl.CreateVertexArrays(1, &d.lineVao);
    gl.CreateBuffers(1, &d.lineVbo);
    gl.VertexArrayVertexBuffer(d.lineVao, 0, d.lineVbo, 0, sizeof(LineVertex));
    gl.EnableVertexArrayAttrib(d.lineVao, 0);
    gl.VertexArrayAttribFormat(d.lineVao, 0, 3, GL_FLOAT, GL_FALSE, offsetof(LineVertex, position));
    gl.VertexArrayAttribBinding(d.lineVao, 0, 0);
    gl.EnableVertexArrayAttrib(d.lineVao, 1);
    gl.VertexArrayAttribFormat(d.lineVao, 1, 4, GL_FLOAT, GL_FALSE, offsetof(LineVertex, colour));
    gl.VertexArrayAttribBinding(d.lineVao, 1, 0);

    gl.CreateVertexArrays(1, &d.rayVao);   // attribute-less: the rays come from gl_VertexID
    gl.CreateBuffers(1, &d.raysBuffer);
    gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &d.raysTexture);
    gl.CreateBuffers(1, &d.selectedBuffer);
    gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &d.selectedTexture);
    gl.CreateBuffers(1, &d.endsBuffer);
    gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &d.endsTexture);
    gl.CreateBuffers(1, &d.overlayBuffer);
    gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &d.overlayTexture);
}

ViewportRenderer::~ViewportRenderer()
{
    Impl& d = *impl_;
    const gl::Functions& gl = d.gl;
    for (GLuint p : {d.meshProgram, d.lineProgram, d.rayProgram, d.overlayProgram})
        gl.DeleteProgram(p);
    GLuint vaos[] = {d.sceneFile.vao, d.occluders.vao, d.lineVao, d.rayVao};
    gl.DeleteVertexArrays(4, vaos);
    GLuint buffers[] = {d.sceneFile.vbo, d.occluders.vbo, d.lineVbo, d.raysBuffer, d.endsBuffer, d.overlayBuffer};
    gl.DeleteBuffers(6, buffers);
    GLuint textures[] = {d.raysTexture, d.endsTexture, d.overlayTexture, d.aoTexture, d.pvsTexture,
                         d.sceneFile.hiddenTexture, d.occluders.hiddenTexture};
    gl.DeleteTextures(7, textures);
    GLuint more[] = {d.pvsBuffer, d.sceneFile.hiddenBuffer, d.occluders.hiddenBuffer, d.selectedBuffer};
    gl.DeleteBuffers(4, more);
    gl.DeleteTextures(1, &d.selectedTexture);
    d.cache.destroy(gl);
    d.compose.destroy(gl);
}

LevelMesh::LevelMesh() = default;
LevelMesh::~LevelMesh() = default;
LevelMesh::LevelMesh(LevelMesh&&) noexcept = default;
LevelMesh& LevelMesh::operator=(LevelMesh&&) noexcept = default;

LevelMesh prepareLevelMesh(const Scene& scene)
{
    LevelMesh mesh;
    mesh.vertices = meshVertices(worldTriangles(scene), nullptr);
    return mesh;
}

void ViewportRenderer::setSceneFile(const Scene& scene) { setSceneFile(prepareLevelMesh(scene)); }

bool ViewportRenderer::levelIncomplete() const { return impl_->levelFirstDraw; }

LevelPass ViewportRenderer::lastLevelPass() const { return impl_->lastPass; }

void ViewportRenderer::setSceneFile(LevelMesh mesh, bool inChunks)
{
    impl_->sceneFileVertices = std::move(mesh.vertices);
    impl_->upload(impl_->sceneFile, impl_->sceneFileVertices);
    impl_->levelFirstDraw = impl_->levelJustUploaded = inChunks && impl_->sceneFile.vertices > 0;
    impl_->aoReady = false;   // its uvs were for the old triangles
    ++impl_->sceneVersion;
}

void ViewportRenderer::setAmbientOcclusion(const std::vector<glm::vec2>& uvs, int width, int height, const std::vector<glm::vec3>& map)
{
    Impl& d = *impl_;
    // The uvs cover the whole scene: the scene file's triangles, then the placed occluders'.
    const std::size_t fileCorners = d.sceneFileVertices.size();
    if (uvs.size() != fileCorners + d.occluderVertices.size() || width < 1 || height < 1 ||
        map.size() != std::size_t(width) * std::size_t(height)) {
        d.aoReady = false;
        ++d.sceneVersion;
        return;   // not this scene's answer (the level or the occluders changed meanwhile)
    }
    const auto take = [&](std::vector<MeshVertex>& vertices, std::size_t first, MeshBuffer& buffer) {
        bool changed = false;
        for (std::size_t k = 0; k < vertices.size(); ++k) {
            changed = changed || vertices[k].aoUv != uvs[first + k];
            vertices[k].aoUv = uvs[first + k];
        }
        if (changed)
            d.upload(buffer, vertices);
        return changed;
    };
    const bool fileUvsChanged = take(d.sceneFileVertices, 0, d.sceneFile);
    take(d.occluderVertices, fileCorners, d.occluders);   // drawn anew every frame
    d.gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    if (d.aoReady && !fileUvsChanged && width == d.aoWidth && height == d.aoHeight) {
        // The same texels, new light: the cached level is lit again, not drawn again.
        d.gl.TextureSubImage2D(d.aoTexture, 0, 0, 0, width, height, GL_RGB, GL_FLOAT, map.data());
        ++d.mapVersion;
        return;
    }
    d.aoReady = false;
    ++d.sceneVersion;
    if (d.aoTexture)
        d.gl.DeleteTextures(1, &d.aoTexture);
    d.gl.CreateTextures(GL_TEXTURE_2D, 1, &d.aoTexture);
    d.gl.TextureStorage2D(d.aoTexture, 1, GL_RGB32F, width, height);
    d.aoWidth = width;
    d.aoHeight = height;
    d.gl.TextureSubImage2D(d.aoTexture, 0, 0, 0, width, height, GL_RGB, GL_FLOAT, map.data());
    d.gl.TextureParameteri(d.aoTexture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    d.gl.TextureParameteri(d.aoTexture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    d.gl.TextureParameteri(d.aoTexture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    d.gl.TextureParameteri(d.aoTexture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    d.aoReady = true;
}

void ViewportRenderer::setPvsCulled(const std::vector<std::uint8_t>& culled)
{
    Impl& d = *impl_;
    ++d.sceneVersion;   // the cached level image is stale
    d.pvsReady = false;
    if (culled.empty())
        return;
    if (!d.pvsBuffer) {
        d.gl.CreateBuffers(1, &d.pvsBuffer);
        d.gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &d.pvsTexture);
    }
    d.gl.NamedBufferData(d.pvsBuffer, GLsizeiptr(culled.size()), culled.data(), GL_STREAM_DRAW);
    d.gl.TextureBuffer(d.pvsTexture, GL_R8UI, d.pvsBuffer);
    d.pvsReady = true;
}

void ViewportRenderer::setHiddenObjects(const std::vector<std::uint8_t>& sceneFile, const std::vector<std::uint8_t>& occluders)
{
    Impl& d = *impl_;
    if (sceneFile != d.sceneFileHidden) {
        ++d.sceneVersion;   // the cached level image is stale (not while only occluders move)
        d.sceneFileHidden = sceneFile;
        d.setHidden(d.sceneFile, sceneFile);
    }
    d.setHidden(d.occluders, occluders);
}

void ViewportRenderer::setOccluders(const Scene& occluders, const std::vector<std::size_t>& occluderOf)
{
    impl_->occluderVertices = meshVertices(worldTriangles(occluders), &occluderOf);
    impl_->upload(impl_->occluders, impl_->occluderVertices);
}

void ViewportRenderer::setHiddenSamples(const HiddenSampleMap* map)
{
    Impl& d = *impl_;
    // Kept, not uploaded: the drawn rays are listed from it when they are next drawn.
    d.map = map && map->rayCount() > 0 ? map : nullptr;
    d.endsCap = 0;
    d.listedMap = nullptr;   // listed for the map before
}

void ViewportRenderer::setDisagreement(const RayDisagreement* disagreement)
{
    Impl& d = *impl_;
    d.disagreement = disagreement && disagreement->rays > 0 ? disagreement : nullptr;
    d.listedDisagreement = nullptr;
    d.listedMap = nullptr;
}

void ViewportRenderer::setSelectedRays(std::vector<std::uint64_t> rays, int sources, int receivers)
{
    Impl& d = *impl_;
    d.selected.clear();
    d.selectedSources = sources;
    d.selectedReceivers = receivers;
    d.selectedListed = false;
    const std::uint64_t total = std::uint64_t(std::max(sources, 0)) * std::uint64_t(std::max(receivers, 0));
    for (const std::uint64_t ray : rays)
        if (ray < total && total <= (std::uint64_t(1) << 30)) {
            const auto j = std::uint32_t(ray / std::uint64_t(sources)), i = std::uint32_t(ray % std::uint64_t(sources));
            d.selected.push_back((i * std::uint32_t(receivers) + j) | 1u << 30);
        }
}

void ViewportRenderer::setRayEnds(const std::vector<float>& ends, int cap)
{
    Impl& d = *impl_;
    d.endsCap = 0;
    if (ends.empty() || cap <= 0 || !d.map)
        return;
    d.gl.NamedBufferData(d.endsBuffer, GLsizeiptr(ends.size() * sizeof(float)), ends.data(), GL_STREAM_DRAW);
    d.gl.TextureBuffer(d.endsTexture, GL_R32F, d.endsBuffer);
    d.endsCap = cap;
}

void ViewportRenderer::setOverlay(ObjectKind patch, const OverlayTexels* texels)
{
    Impl& d = *impl_;
    d.overlayPatch = ObjectKind::None;
    if (!texels || texels->empty() || (patch != ObjectKind::Source && patch != ObjectKind::Receiver))
        return;
    d.gl.NamedBufferData(d.overlayBuffer, GLsizeiptr(texels->rgba.size()), texels->rgba.data(), GL_STREAM_DRAW);
    d.gl.TextureBuffer(d.overlayTexture, GL_RGBA8, d.overlayBuffer);
    d.overlayPatch = patch;
    d.overlayNa = texels->na;
    d.overlayNb = texels->nb;
    d.overlaySmooth = texels->smooth;
}

namespace {

/// FrameState::lights as lines; each marker keeps a steady size on screen.
void appendLightMarkers(std::vector<LineVertex>& lines, const FrameState& f)
{
    for (std::size_t k = 0; k < f.lights.size(); ++k) {
        const Light& light = f.lights[k];
        const bool selected = f.selection.kind == ObjectKind::Light && f.selection.index == k;
        const double brightest = std::max({light.colour.r, light.colour.g, light.colour.b, 1e-9});
        const glm::vec4 colour = selected ? glm::vec4(1.0f, 0.6f, 0.1f, 1.0f)
                                          : glm::vec4(glm::mix(glm::vec3(light.colour / brightest), glm::vec3(1.0f, 0.95f, 0.6f), 0.5f), 0.95f);
        const glm::dvec3 pivot = lightPivot(light, f.sunLevel);
        const double arm = std::max(0.008 * glm::length(pivot - f.camera.eye()), 0.02) * (selected ? 1.6 : 1.0);
        auto line = [&](const glm::dvec3& a, const glm::dvec3& b) {
            lines.push_back({glm::vec3(a), colour});
            lines.push_back({glm::vec3(b), colour});
        };
        auto star = [&](const glm::dvec3& at) {
            for (int axis = 0; axis < 3; ++axis) {
                glm::dvec3 reach(0.0);
                reach[axis] = arm;
                line(at - reach, at + reach);
            }
            const double diagonal = arm / std::sqrt(3.0);
            line(at - glm::dvec3(diagonal), at + glm::dvec3(diagonal));
            line(at - glm::dvec3(diagonal, -diagonal, diagonal), at + glm::dvec3(diagonal, -diagonal, diagonal));
        };
        const glm::dvec3 d = glm::length(light.direction) > 0.0 ? glm::normalize(light.direction) : glm::dvec3(0.0, -1.0, 0.0);
        switch (light.type) {
        case LightType::Point: star(pivot); break;
        case LightType::Spot: {
            star(pivot);
            // The outer cone, 4 arms long: four edges and the rim.
            const glm::dvec3 x = glm::normalize(glm::cross(std::abs(d.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0), d));
            const glm::dvec3 y = glm::cross(d, x);
            const double length = 4.0 * arm, radius = length * std::tan(light.outerAngle);
            glm::dvec3 previous{};
            for (int s = 0; s <= 16; ++s) {
                const double a = 2.0 * 3.141592653589793 * s / 16.0;
                const glm::dvec3 rim = pivot + length * d + radius * (std::cos(a) * x + std::sin(a) * y);
                if (s > 0)
                    line(previous, rim);
                if (s % 4 == 0 && s < 16)
                    line(pivot, rim);
                previous = rim;
            }
            break;
        }
        case LightType::Directional: {
            star(pivot);
            const glm::dvec3 tip = pivot + 8.0 * arm * d;
            line(pivot, tip);
            const glm::dvec3 side = glm::normalize(glm::cross(std::abs(d.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0), d));
            line(tip, tip - 2.0 * arm * d + arm * side);
            line(tip, tip - 2.0 * arm * d - arm * side);
            break;
        }
        case LightType::Area: {
            const Patch& a = light.area;
            const int around[4] = {0, 1, 3, 2};   // cornerPoint's order is c, c+u, c+v, c+u+v
            for (int c = 0; c < 4; ++c)
                line(a.cornerPoint(around[c]), a.cornerPoint(around[(c + 1) % 4]));
            line(a.cornerPoint(0), a.cornerPoint(3));
            line(a.cornerPoint(1), a.cornerPoint(2));
            const glm::dvec3 n = glm::normalize(glm::cross(a.u, a.v));
            line(pivot, pivot + 4.0 * arm * n);
            if (light.twoSided)
                line(pivot, pivot - 4.0 * arm * n);
            break;
        }
        }
    }
}

/// The source, the receiver and the placement ghost: each a tinted quad (none over the overlay)
/// and its edges.
void appendPatchQuads(std::vector<LineVertex>& triangles, std::vector<LineVertex>& lines, const FrameState& f,
                      const Patch* overlaid)
{
    auto quad = [&](const Patch& patch, const glm::vec4& colour) {
        const glm::vec3 c(patch.corner), u(patch.u), v(patch.v);
        if (&patch != overlaid)   // a tint over the overlay would change its colours
            for (const glm::vec3& p : {c, c + u, c + u + v, c, c + u + v, c + v})
                triangles.push_back({p, colour});
        const glm::vec4 edge(glm::vec3(colour) * 1.2f, 1.0f);
        const glm::vec3 corners[4] = {c, c + u, c + u + v, c + v};
        for (int k = 0; k < 4; ++k) {
            lines.push_back({corners[k], edge});
            lines.push_back({corners[(k + 1) % 4], edge});
        }
    };
    const bool sourceSelected = f.selection.kind == ObjectKind::Source, receiverSelected = f.selection.kind == ObjectKind::Receiver;
    if (!f.sourceHidden)
        quad(f.source, sourceSelected ? glm::vec4(0.5f, 1.0f, 0.5f, 0.55f) : glm::vec4(0.25f, 0.8f, 0.35f, 0.45f));
    if (!f.receiverHidden)
        quad(f.receiver, receiverSelected ? glm::vec4(0.5f, 0.7f, 1.0f, 0.55f) : glm::vec4(0.25f, 0.5f, 0.95f, 0.45f));
    if (f.placementGhost)
        quad(*f.placementGhost, glm::vec4(1.0f, 1.0f, 1.0f, 0.3f));
}

/// The occluder assistant's suggestion, magenta, over everything: it often stands in a
/// doorway's wall, where a depth-tested fill would hide.
void appendOccluderGhost(std::vector<LineVertex>& ghostFill, std::vector<LineVertex>& overlay, const FrameState& f)
{
    if (f.occluderGhost.size() >= 3) {
        const std::vector<glm::vec3>& ghost = f.occluderGhost;
        const glm::vec4 fill(1.0f, 0.25f, 0.9f, 0.3f), edge(1.0f, 0.45f, 1.0f, 1.0f);
        for (std::size_t k = 1; k + 1 < ghost.size(); ++k)
            for (const glm::vec3& p : {ghost[0], ghost[k], ghost[k + 1]})
                ghostFill.push_back({p, fill});
        for (std::size_t k = 0; k < ghost.size(); ++k) {
            overlay.push_back({ghost[k], edge});
            overlay.push_back({ghost[(k + 1) % ghost.size()], edge});
        }
    }
}

/// The shaft: corresponding corners joined; red when the pair cannot be sampled.
void appendShaft(std::vector<LineVertex>& lines, const FrameState& f)
{
    const glm::vec4 shaftColour = f.pairValid ? glm::vec4(0.9f, 0.9f, 0.9f, 0.5f) : glm::vec4(1.0f, 0.2f, 0.2f, 0.9f);
    for (int k = 0; k < 4; ++k) {
        const glm::dvec3 s = f.source.cornerPoint(k);
        const glm::dvec3 r = f.receiver.cornerPoint(k);
        lines.push_back({glm::vec3(s), shaftColour});
        lines.push_back({glm::vec3(r), shaftColour});
    }
}

/// The cut plane's outline over the level's box, where the cut walls end.
void appendCutOutline(std::vector<LineVertex>& lines, const FrameState& f, const Cutaway& cut)
{
    if (std::isfinite(cut.height) && !f.levelBounds.empty() && f.cutHandle && cut.height > f.levelBounds.min.y &&
        cut.height < f.levelBounds.max.y) {
        const glm::vec4 outline(kCutColour, f.cutHandleHovered ? 0.9f : 0.6f);
        const float y = float(cut.height);
        const glm::vec3 corners[4] = {{f.levelBounds.min.x, y, f.levelBounds.min.z}, {f.levelBounds.max.x, y, f.levelBounds.min.z},
                                      {f.levelBounds.max.x, y, f.levelBounds.max.z}, {f.levelBounds.min.x, y, f.levelBounds.max.z}};
        for (int k = 0; k < 4; ++k) {
            lines.push_back({corners[k], outline});
            lines.push_back({corners[(k + 1) % 4], outline});
        }
    }
}

/// PVS gaps: a cross at the opening, a witness ray through it for the shown cell's gaps, and
/// the selected gap's witnesses (bright for the selected gap).
void appendGapMarkers(std::vector<LineVertex>& overlay, const FrameState& f)
{
    const glm::vec4 witness(kSelectedRayRgb[0] / 255.0f, kSelectedRayRgb[1] / 255.0f, kSelectedRayRgb[2] / 255.0f, 1.0f);
    for (const auto& [from, to] : f.gapWitnesses) {
        overlay.push_back({from, glm::vec4(glm::vec3(witness), 0.5f)});
        overlay.push_back({to, witness});
    }
    for (std::size_t k = 0; k < f.gapMarkers.size(); ++k) {
        const bool picked = int(k) == f.gapSelected;
        const glm::vec4 ray = picked ? glm::vec4(1.0f, 1.0f, 0.85f, 1.0f) : glm::vec4(1.0f, 0.55f, 0.1f, 0.9f);
        const auto& marker = f.gapMarkers[k];
        if (marker.ray || picked) {
            overlay.push_back({marker.from, glm::vec4(glm::vec3(ray), 0.35f)});
            overlay.push_back({marker.to, ray});
        }
        // The cross keeps a steady size on screen: a fraction of the distance to the eye.
        const float arm = float(0.015 * glm::length(glm::dvec3(marker.at) - f.camera.eye())) * (picked ? 2.0f : 1.0f);
        for (int axis = 0; axis < 3; ++axis) {
            glm::vec3 reach(0.0f);
            reach[axis] = arm;
            overlay.push_back({marker.at - reach, ray});
            overlay.push_back({marker.at + reach, ray});
        }
    }
}

/// The PVS debugger's shown view cell, its box's 12 edges.
void appendViewCell(std::vector<LineVertex>& overlay, const FrameState& f)
{
    if (f.viewCell) {
        const glm::vec4 colour(kViewCellRgb[0] / 255.0f, kViewCellRgb[1] / 255.0f, kViewCellRgb[2] / 255.0f, 1.0f);
        const glm::vec3 lo = f.viewCell->min, hi = f.viewCell->max;
        const auto corner = [&](int k) { return glm::vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z); };
        for (int a = 0; a < 8; ++a)
            for (int bit = 1; bit < 8; bit <<= 1)
                if (!(a & bit)) {   // each of the box's 12 edges once
                    overlay.push_back({corner(a), colour});
                    overlay.push_back({corner(a | bit), colour});
                }
    }
}

/// The selected light's scissor rectangle, dashed.
void appendScissorFrame(std::vector<LineVertex>& overlay, const FrameState& f)
{
    if (f.scissor) {   // a dashed frame just beyond the near plane, over everything
        const glm::dvec4 r = *f.scissor;
        const glm::vec4 colour(1.0f, 0.85f, 0.2f, 0.9f);
        const double depth = 0.02 * f.camera.distance;
        auto at = [&](double x, double y) {
            const Ray ray = pixelRay(f.camera, x, y, f.width, f.height);
            return glm::vec3(ray.origin + ray.direction * (depth / std::max(glm::dot(ray.direction, f.camera.forward()), 1e-6)));
        };
        const glm::dvec2 corners[4] = {{r.x, r.y}, {r.z, r.y}, {r.z, r.w}, {r.x, r.w}};
        for (int k = 0; k < 4; ++k) {
            const glm::dvec2 a = corners[k], b = corners[(k + 1) % 4];
            const int dashes = std::max(1, int(glm::length(b - a) / 12.0));
            for (int i = 0; i < dashes; i += 2) {
                overlay.push_back({at(glm::mix(a, b, double(i) / dashes).x, glm::mix(a, b, double(i) / dashes).y), colour});
                overlay.push_back({at(glm::mix(a, b, double(i + 1) / dashes).x, glm::mix(a, b, double(i + 1) / dashes).y), colour});
            }
        }
    }
}

} // namespace

void ViewportRenderer::Impl::setCut(double height, double depth)
{
    // Finite values only: "no cut" as an infinite distance reached the clip distances as infinite
    // (or NaN) and llvmpipe dropped every triangle of the placed occluders, which are drawn uncut.
    gl.ProgramUniform1f(meshProgram, loc(meshProgram, "cutHeight"), float(std::min(height, 1e30)));
    gl.ProgramUniform1f(meshProgram, loc(meshProgram, "cutDepth"), float(std::max(depth, -1e30)));
}

/// The level's vertices [first, end) into `framebuffer` (a first draw comes in chunks: kFirstDrawChunk).
void ViewportRenderer::Impl::drawLevel(const FrameState& f, const FrameSetup& s, GLuint framebuffer, bool clear,
                                       GLsizei first, GLsizei end)
{
    Impl& d = *this;
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    gl.Viewport(0, 0, f.width, f.height);
    if (clear) {
        const float background[4] = {0.17f, 0.18f, 0.2f, 1.0f};
        gl.ClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, background);
        gl.ClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    }
    gl.UseProgram(d.meshProgram);
    d.setCut(s.cut.height, s.cut.depth);
    gl.Enable(GL_CLIP_DISTANCE0);
    gl.Enable(GL_CLIP_DISTANCE1);
    gl.Enable(GL_CLIP_DISTANCE2);
    gl.Enable(GL_POLYGON_OFFSET_FILL);
    gl.PolygonOffset(1.0f, 1.0f);   // the wireframe overlay wins the depth test
    d.drawMesh(d.sceneFile, {0.72f, 0.72f, 0.7f}, s.selectedFile, glm::vec4(0.0f), first, end);
    gl.Disable(GL_POLYGON_OFFSET_FILL);
    if (f.style.wireframe) {
        gl.PolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        d.drawMesh(d.sceneFile, {}, -1, {0.1f, 0.1f, 0.12f, 1.0f}, first, end);
        gl.PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
    gl.Disable(GL_CLIP_DISTANCE0);
    gl.Disable(GL_CLIP_DISTANCE1);
    gl.Disable(GL_CLIP_DISTANCE2);
}

/// The level into the frame: from the cache, drawn again only when its key changed (in chunks
/// on a first draw), or whole where the cache cannot be blitted. Returns where the frame is composed.
GLuint ViewportRenderer::Impl::composeLevel(const FrameState& f, const FrameSetup& s)
{
    Impl& d = *this;
    const Impl::BackgroundKey key{s.viewProj, f.width, f.height, f.style.wireframe, float(s.cut.height), float(s.cut.depth),
                                  s.selectedFile, d.sceneVersion, s.ao, f.style.litView, s.pvs};
    bool drawn = false;
    GLuint target = f.framebuffer;   // where the frame is composed
    d.resizeCache(f.width, f.height);
    if (!d.cacheBroken) {
        if (d.cacheKey != key) {
            d.cacheKey = key;
            d.cacheLevelDrawn = -1;
        }
        const GLsizei total = d.sceneFile.vertices;
        d.lastPass = LevelPass::Cached;
        // Light maps arriving for the same uvs (a light dragged, the lit view converging).
        const bool mapChanged = s.ao && d.cacheMapVersion != d.mapVersion;
        if (mapChanged && d.cacheLevelDrawn >= total && !d.cacheRelightable)
            d.cacheLevelDrawn = -1;   // drawn without its surfaces: once more with them
        if (d.cacheLevelDrawn < total) {
            const GLsizei from = std::max<GLsizei>(d.cacheLevelDrawn, 0);
            const GLsizei to = !d.levelFirstDraw     ? total
                               : d.levelJustUploaded ? from
                                                     : std::min(total, from + Impl::kFirstDrawChunk);
            const bool clear = d.cacheLevelDrawn < 0;
            if (clear) {
                // The surfaces cost a software rasteriser 32 bytes a pixel more on every draw:
                // written only while maps arrive, not while the camera orbits a settled view.
                d.cacheRelightable = mapChanged;
                d.relight.setWriting(d.cacheRelightable);
                if (d.cacheRelightable)
                    d.relight.clear();
                d.cacheMapVersion = d.mapVersion;
            }
            d.drawLevel(f, s, d.cache.framebuffer, clear, from, to);
            d.cacheLevelDrawn = to;
            d.lastPass = LevelPass::Drawn;
            if (to >= total)
                d.levelFirstDraw = false;
        } else if (mapChanged) {
            d.relight.relight(f.style.litView);
            d.cacheMapVersion = d.mapVersion;
            d.lastPass = LevelPass::Relit;
        }
        d.levelJustUploaded = false;
        while (gl.GetError() != GL_NO_ERROR) {
        }
        gl.BlitNamedFramebuffer(d.cache.framebuffer, d.compose.framebuffer, 0, 0, f.width, f.height, 0, 0, f.width,
                                f.height, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, GL_NEAREST);
        drawn = gl.GetError() == GL_NO_ERROR;
        d.cacheBroken = !drawn;
        if (drawn)
            target = d.compose.framebuffer;
    }
    if (!drawn) {   // without the cache, every frame draws the level whole
        d.drawLevel(f, s, f.framebuffer, true, 0, std::numeric_limits<GLsizei>::max());
        d.levelFirstDraw = d.levelJustUploaded = false;
    }
    return target;
}

/// Placed occluders: always drawn (they move), never cut away.
void ViewportRenderer::Impl::drawOccluders(const FrameState& f, int selectedOccluder)
{
    Impl& d = *this;
    gl.UseProgram(d.meshProgram);
    d.setCut(std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity());
    gl.Enable(GL_CLIP_DISTANCE2);   // hidden ones
    d.drawMesh(d.occluders, kOccluderColour, selectedOccluder, glm::vec4(0.0f));
    if (f.style.wireframe) {
        gl.PolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        d.drawMesh(d.occluders, {}, -1, {0.1f, 0.1f, 0.3f, 1.0f});
        gl.PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
    gl.Disable(GL_CLIP_DISTANCE2);
}

/// The importance overlay on its patch, opaque (depth written, so translucent things behind it stay
/// behind it). Returns the patch it covers, or null.
const Patch* ViewportRenderer::Impl::drawOverlay(const FrameState& f, const glm::vec3& eye)
{
    Impl& d = *this;
    const Patch* overlaid = d.overlayPatch == ObjectKind::Source && !f.sourceHidden       ? &f.source
                            : d.overlayPatch == ObjectKind::Receiver && !f.receiverHidden ? &f.receiver
                                                                                         : nullptr;
    if (overlaid && (overlaid->na != d.overlayNa || overlaid->nb != d.overlayNb))
        overlaid = nullptr;   // the grid changed since the upload: the colours belong to another grid
    if (overlaid) {
        const GLuint p = d.overlayProgram;
        auto vec3 = [&](const char* name, const glm::dvec3& v) {
            const glm::vec3 x(v);
            gl.ProgramUniform3fv(p, d.loc(p, name), 1, glm::value_ptr(x));
        };
        // Lifted towards the eye by a millimetre a metre of patch, and pulled forward in depth, so
        // it wins against the patch's own plane and the surface the patch was placed on (2 cm).
        const glm::dvec3 n = glm::normalize(glm::cross(overlaid->u, overlaid->v));
        const double side = glm::dot(glm::dvec3(eye) - overlaid->corner, n) >= 0.0 ? 1.0 : -1.0;
        const double size = std::max(glm::length(overlaid->u), glm::length(overlaid->v));
        vec3("corner", overlaid->corner);
        vec3("edgeU", overlaid->u);
        vec3("edgeV", overlaid->v);
        vec3("lift", side * 1e-3 * size * n);
        gl.ProgramUniform2i(p, d.loc(p, "grid"), d.overlayNa, d.overlayNb);
        gl.ProgramUniform1i(p, d.loc(p, "smoothing"), d.overlaySmooth ? 1 : 0);
        gl.UseProgram(p);
        gl.BindTextureUnit(1, d.overlayTexture);
        gl.BindVertexArray(d.rayVao);   // attribute-less too
        gl.Enable(GL_POLYGON_OFFSET_FILL);
        gl.PolygonOffset(-1.0f, -1.0f);
        gl.DrawArrays(GL_TRIANGLES, 0, 6);
        gl.Disable(GL_POLYGON_OFFSET_FILL);
    }
    return overlaid;
}

/// The rays between the patches' samples (RayLayer.h), translucent, without writing depth; leaves
/// blending on and depth writes off for the guides. Returns how many were drawn.
std::uint64_t ViewportRenderer::Impl::drawRays(const FrameState& f, const glm::mat4& viewProj, GLuint target)
{
    Impl& d = *this;
    // Translucent: rays, then the patches, without writing depth.
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl.DepthMask(GL_FALSE);
    std::uint64_t raysDrawn = 0;
    // The map may answer an older pair (a background answer on its way): rays only while its
    // sample counts are these patches'.
    const bool mapFits = d.map && d.map->sourceCount() == f.source.na * f.source.nb &&
                         d.map->receiverCount() == f.receiver.na * f.receiver.nb;
    const bool disagreementFits = d.disagreement && d.disagreement->falseBlocked.sourceCount() == f.source.na * f.source.nb &&
                                  d.disagreement->falseBlocked.receiverCount() == f.receiver.na * f.receiver.nb;
    if (f.style.showRays && f.pairValid && disagreementFits)
        return drawDisagreement(f);
    if (f.style.showRays && f.pairValid && mapFits) {
        const RaySubset subset = raySubset(d.map->sourceCount(), d.map->receiverCount(), f.style.rayCap);
        const GLuint p = d.rayProgram;
        setRayUniforms(f, subset);
        gl.ProgramUniform1i(p, d.loc(p, "showBlocked"), f.style.showBlocked ? 1 : 0);
        gl.ProgramUniform1i(p, d.loc(p, "disagreement"), 0);
        // Readable from 1k to 1M rays (RayLayer.h): each ray's opacity from how many
        // drawn rays cross a pixel of the bundle, so that an open shaft reaches the style's
        // coverage; dense bundles are drawn into a coarser coverage layer, then laid over the frame.
        const std::optional<BundleOnScreen> bundle = bundleOnScreen(viewProj, f.width, f.height, f.source, f.receiver);
        const double overlap =
            bundle ? expectedOverlap(*bundle, subset.count())
                   : double(subset.count()) * 0.5 * (f.width + f.height) / (double(f.width) * double(f.height));
        const int divisor = rayLayerDivisor(overlap);
        float freeAlpha = rayOpacity(f.style.freeColour.a, overlap, divisor);
        float blockedAlpha = rayOpacity(f.style.blockedColour.a, overlap, divisor);
        const bool useEnds = f.style.showBlocked && d.endsCap == f.style.rayCap;
        gl.ProgramUniform1i(p, d.loc(p, "useEnds"), useEnds ? 1 : 0);
        gl.ProgramUniform1i(p, d.loc(p, "marks"), 0);
        gl.ProgramUniform4fv(p, d.loc(p, "stopColour"), 1, glm::value_ptr(f.style.stopColour));
        // Blocked rays hidden: only the free ones are drawn (in a level most rays are blocked,
        // and each would cost its vertex work only to be clipped). Listed once per answer.
        const bool indirect = !f.style.showBlocked;
        if (d.listedMap != d.map || d.listedFree != indirect || d.listedSubset.receivers != subset.receivers ||
            d.listedSubset.receiverStride != subset.receiverStride ||
            d.listedSubset.sourcePerReceiver != subset.sourcePerReceiver ||
            d.listedSubset.sourceStride != subset.sourceStride) {
            const std::vector<std::uint32_t> list = indirect ? freeDrawnRays(*d.map, subset) : blockedDrawnRays(*d.map, subset);
            gl.NamedBufferData(d.raysBuffer, GLsizeiptr(std::max<std::size_t>(list.size(), 1) * sizeof(std::uint32_t)),
                               list.empty() ? nullptr : list.data(), GL_STREAM_DRAW);
            gl.TextureBuffer(d.raysTexture, GL_R32UI, d.raysBuffer);
            d.listedMap = d.map;
            d.listedSubset = subset;
            d.listedFree = indirect;
            d.freeCount = indirect ? GLsizei(list.size()) : 0;
        }
        gl.ProgramUniform1i(p, d.loc(p, "indirect"), indirect ? 1 : 0);
        gl.BindTextureUnit(0, d.raysTexture);
        gl.BindTextureUnit(2, d.endsTexture);
        gl.BindVertexArray(d.rayVao);
        // Sparse rays go straight into the frame (a layer at full size would only add its copies).
        const bool layered = divisor > 1 && d.rayLayer.begin(target, f.width, f.height, divisor, f.style.showBlocked);
        if (layered) {
            // Counts: free rays in red, blocked ones in green.
            const glm::vec4 free(1.0f, 0.0f, 0.0f, 0.0f), blocked(0.0f, 1.0f, 0.0f, 0.0f);
            gl.ProgramUniform4fv(p, d.loc(p, "freeColour"), 1, glm::value_ptr(free));
            gl.ProgramUniform4fv(p, d.loc(p, "blockedColour"), 1, glm::value_ptr(blocked));
        } else {
            if (divisor > 1) {   // no layer could be made: the full-resolution opacities
                freeAlpha = rayOpacity(f.style.freeColour.a, overlap, 1);
                blockedAlpha = rayOpacity(f.style.blockedColour.a, overlap, 1);
            }
            const glm::vec4 free(glm::vec3(f.style.freeColour), freeAlpha), blocked(glm::vec3(f.style.blockedColour), blockedAlpha);
            gl.ProgramUniform4fv(p, d.loc(p, "freeColour"), 1, glm::value_ptr(free));
            gl.ProgramUniform4fv(p, d.loc(p, "blockedColour"), 1, glm::value_ptr(blocked));
        }
        gl.UseProgram(p);
        gl.DrawArrays(GL_LINES, 0, indirect ? 2 * d.freeCount : GLsizei(2 * subset.count()));
        if (layered) {
            const glm::dvec2 lo = bundle ? bundle->min : glm::dvec2(0.0), hi = bundle ? bundle->max : glm::dvec2(f.width, f.height);
            d.rayLayer.composite(target, f.width, f.height, lo, hi, glm::vec4(glm::vec3(f.style.freeColour), freeAlpha),
                                 glm::vec4(glm::vec3(f.style.blockedColour), blockedAlpha));
            gl.Enable(GL_DEPTH_TEST);
            gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
            gl.UseProgram(p);
            gl.BindTextureUnit(0, d.raysTexture);
            gl.BindVertexArray(d.rayVao);
        }
        if (useEnds) {   // the dots, at full resolution
            gl.Enable(GL_PROGRAM_POINT_SIZE);
            gl.ProgramUniform1i(p, d.loc(p, "marks"), 1);
            gl.DrawArrays(GL_POINTS, 0, GLsizei(subset.count()));
            gl.Disable(GL_PROGRAM_POINT_SIZE);
        }
        raysDrawn = subset.count();
    }
    if (f.style.showRays && f.pairValid && !d.selected.empty() && d.selectedSources == f.source.na * f.source.nb &&
        d.selectedReceivers == f.receiver.na * f.receiver.nb)
        drawSelectedRays(f);
    return raysDrawn;
}

/// The ray program set to draw a list of classed rays (disagreementDrawnRays' form) of the whole
/// `sources` x `receivers` pair, whole, from texture unit 0.
void ViewportRenderer::Impl::setListedRayUniforms(const FrameState& f, int sources, int receivers)
{
    const GLuint p = rayProgram;
    RaySubset whole;
    whole.receivers = std::uint32_t(receivers);
    whole.sourcePerReceiver = std::uint32_t(sources);
    setRayUniforms(f, whole);
    gl.ProgramUniform1i(p, loc(p, "showBlocked"), 1);
    gl.ProgramUniform1i(p, loc(p, "useEnds"), 0);
    gl.ProgramUniform1i(p, loc(p, "marks"), 0);
    gl.ProgramUniform1i(p, loc(p, "indirect"), 1);
    gl.ProgramUniform1i(p, loc(p, "disagreement"), 1);
}

/// The picked opening's rays (setSelectedRays), opaque over the rays' haze.
void ViewportRenderer::Impl::drawSelectedRays(const FrameState& f)
{
    const GLuint p = rayProgram;
    if (!selectedListed) {
        gl.NamedBufferData(selectedBuffer, GLsizeiptr(selected.size() * sizeof(std::uint32_t)), selected.data(), GL_STREAM_DRAW);
        gl.TextureBuffer(selectedTexture, GL_R32UI, selectedBuffer);
        selectedListed = true;
    }
    setListedRayUniforms(f, selectedSources, selectedReceivers);
    const glm::vec4 colour(kSelectedRayRgb[0] / 255.0f, kSelectedRayRgb[1] / 255.0f, kSelectedRayRgb[2] / 255.0f, 0.95f);
    gl.ProgramUniform4fv(p, loc(p, "falseBlockedColour"), 1, glm::value_ptr(colour));
    gl.UseProgram(p);
    gl.BindTextureUnit(0, selectedTexture);
    gl.BindVertexArray(rayVao);
    gl.DrawArrays(GL_LINES, 0, 2 * GLsizei(selected.size()));
    gl.BindTextureUnit(0, raysTexture);
}

/// The pair's grids and the drawn subset, for the ray program.
void ViewportRenderer::Impl::setRayUniforms(const FrameState& f, const RaySubset& subset)
{
    const GLuint p = rayProgram;
    auto vec3 = [&](const char* name, const glm::dvec3& v) {
        const glm::vec3 x(v);
        gl.ProgramUniform3fv(p, loc(p, name), 1, glm::value_ptr(x));
    };
    vec3("sourceCorner", f.source.corner);
    vec3("sourceU", f.source.u);
    vec3("sourceV", f.source.v);
    gl.ProgramUniform2i(p, loc(p, "sourceGrid"), f.source.na, f.source.nb);
    vec3("receiverCorner", f.receiver.corner);
    vec3("receiverU", f.receiver.u);
    vec3("receiverV", f.receiver.v);
    gl.ProgramUniform2i(p, loc(p, "receiverGrid"), f.receiver.na, f.receiver.nb);
    gl.ProgramUniform1ui(p, loc(p, "receivers"), subset.receivers);
    gl.ProgramUniform1ui(p, loc(p, "receiverStride"), subset.receiverStride);
    gl.ProgramUniform1ui(p, loc(p, "sourceStride"), subset.sourceStride);
}

/// The rays an approximation answers differently (setDisagreement), straight into the frame:
/// they are few where the approximation is good, and each one matters, so each is drawn at a
/// fixed, readable opacity instead of thinning into a haze. Returns how many were drawn.
std::uint64_t ViewportRenderer::Impl::drawDisagreement(const FrameState& f)
{
    const GLuint p = rayProgram;
    const RayDisagreement& dis = *disagreement;
    const auto cap = std::uint32_t(std::max(f.style.rayCap, 16384));   // each disagreement matters: more than the haze
    if (listedDisagreement != disagreement || listedDisagreementCap != cap) {
        const std::vector<std::uint32_t> list = disagreementDrawnRays(dis, cap);
        gl.NamedBufferData(raysBuffer, GLsizeiptr(std::max<std::size_t>(list.size(), 1) * sizeof(std::uint32_t)),
                           list.empty() ? nullptr : list.data(), GL_STREAM_DRAW);
        gl.TextureBuffer(raysTexture, GL_R32UI, raysBuffer);
        listedDisagreement = disagreement;
        listedDisagreementCap = cap;
        listedMap = nullptr;   // the buffer no longer lists the map's rays
        disagreementCount = GLsizei(list.size());
    }
    setListedRayUniforms(f, dis.falseBlocked.sourceCount(), dis.falseBlocked.receiverCount());
    // Opaque while few; past a few thousand, fainter so that a dense band still shows its shape.
    const float alpha = disagreementCount <= 2048 ? 0.95f : std::max(0.35f, 0.95f * std::sqrt(2048.0f / float(disagreementCount)));
    auto colour = [&](const char* name, const std::uint8_t rgb[3]) {
        const glm::vec4 c(rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f, alpha);
        gl.ProgramUniform4fv(p, loc(p, name), 1, glm::value_ptr(c));
    };
    colour("falseBlockedColour", kFalseBlockedRgb);
    colour("falseFreeColour", kFalseFreeRgb);
    colour("tieColour", kTieRgb);
    gl.UseProgram(p);
    gl.BindTextureUnit(0, raysTexture);
    gl.BindVertexArray(rayVao);
    gl.DrawArrays(GL_LINES, 0, 2 * disagreementCount);
    return std::uint64_t(disagreementCount);
}

/// The patches, the shaft, the cut's outline, PVS gaps, lights, the scissor frame and the handles.
void ViewportRenderer::Impl::drawGuides(const FrameState& f, const Patch* overlaid, const Cutaway& cut)
{
    Impl& d = *this;
    std::vector<LineVertex> triangles, lines, overlay;
    appendPatchQuads(triangles, lines, f, overlaid);
    std::vector<LineVertex> ghostFill;
    appendOccluderGhost(ghostFill, overlay, f);
    appendShaft(lines, f);
    appendCutOutline(lines, f, cut);
    appendGapMarkers(overlay, f);
    appendViewCell(overlay, f);
    appendLightMarkers(overlay, f);
    appendScissorFrame(overlay, f);
    std::vector<LineVertex> handles;   // triangles, over everything
    if (f.cutHandle)
        appendCutHandle(handles, *f.cutHandle, f.camera, f.cutHandleHovered);
    if (f.gizmo)
        appendGizmoHandles(handles, *f.gizmo, f.gizmoMode, f.camera, f.hoveredAxis);
    auto drawLines = [&](const std::vector<LineVertex>& vertices, GLenum mode) {
        if (vertices.empty())
            return;
        gl.NamedBufferData(d.lineVbo, GLsizeiptr(vertices.size() * sizeof(LineVertex)), vertices.data(), GL_STREAM_DRAW);
        gl.UseProgram(d.lineProgram);
        gl.BindVertexArray(d.lineVao);
        gl.DrawArrays(mode, 0, GLsizei(vertices.size()));
    };
    drawLines(triangles, GL_TRIANGLES);
    drawLines(lines, GL_LINES);
    gl.Disable(GL_DEPTH_TEST);
    drawLines(ghostFill, GL_TRIANGLES);
    drawLines(overlay, GL_LINES);
    drawLines(handles, GL_TRIANGLES);
    gl.DepthMask(GL_TRUE);
    gl.Disable(GL_BLEND);
}

void ViewportRenderer::render(const FrameState& f)
{
    Impl& d = *impl_;
    const gl::Functions& gl = d.gl;
    Impl::FrameSetup s;
    // The radius sets the depth range. It is rounded up to a power of two: the editor's includes
    // the patches, and a receiver dragged past the level's bounds would otherwise change the
    // projection, and so redraw the cached level (most of a frame on a software rasteriser), on
    // every frame of the drag.
    const double radius = std::exp2(std::ceil(std::log2(std::max(f.sceneRadius, 1.0))));
    s.viewProj = f.camera.projection(double(f.width) / f.height, radius) * f.camera.view();
    const glm::vec3 eye(f.camera.eye());
    const glm::vec3 forward(f.camera.forward());
    for (GLuint p : {d.meshProgram, d.lineProgram, d.rayProgram, d.overlayProgram})
        gl.ProgramUniformMatrix4fv(p, d.loc(p, "viewProj"), 1, GL_FALSE, glm::value_ptr(s.viewProj));
    gl.ProgramUniform3fv(d.meshProgram, d.loc(d.meshProgram, "eye"), 1, glm::value_ptr(eye));
    gl.ProgramUniform3fv(d.meshProgram, d.loc(d.meshProgram, "viewForward"), 1, glm::value_ptr(forward));
    gl.ProgramUniform1i(d.meshProgram, d.loc(d.meshProgram, "orthographic"), f.camera.orthographic ? 1 : 0);
    s.cut = cutaway(f);
    s.selectedFile = f.selection.kind == ObjectKind::SceneObject ? int(f.selection.index) : -1;
    const int selectedOccluder = f.selection.kind == ObjectKind::Occluder ? int(f.selection.index) : -1;

    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LEQUAL);
    gl.DepthMask(GL_TRUE);
    gl.Disable(GL_BLEND);
    gl.Disable(GL_CULL_FACE);
    s.ao = (f.style.ambientOcclusion || f.style.litView) && d.aoReady;
    gl.ProgramUniform1i(d.meshProgram, d.loc(d.meshProgram, "aoOn"), s.ao ? 1 : 0);
    gl.ProgramUniform1i(d.meshProgram, d.loc(d.meshProgram, "litOn"), f.style.litView ? 1 : 0);
    if (s.ao)
        gl.BindTextureUnit(3, d.aoTexture);
    s.pvs = (f.style.pvsDebugger || f.style.lightSets) && d.pvsReady;
    gl.ProgramUniform1i(d.meshProgram, d.loc(d.meshProgram, "pvsOn"), s.pvs ? 1 : 0);
    if (s.pvs)
        gl.BindTextureUnit(4, d.pvsTexture);

    const GLuint target = d.composeLevel(f, s);
    gl.BindFramebuffer(GL_FRAMEBUFFER, target);
    gl.Viewport(0, 0, f.width, f.height);
    d.drawOccluders(f, selectedOccluder);
    const Patch* overlaid = d.drawOverlay(f, eye);
    raysDrawn_ = d.drawRays(f, s.viewProj, target);
    d.drawGuides(f, overlaid, s.cut);

    if (target != f.framebuffer)
        gl.BlitNamedFramebuffer(target, f.framebuffer, 0, 0, f.width, f.height, 0, 0, f.width, f.height,
                                GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl.BindFramebuffer(GL_FRAMEBUFFER, f.framebuffer);
    gl.BindVertexArray(0);
    gl.UseProgram(0);
}

} // namespace sightline::ui
