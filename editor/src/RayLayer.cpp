#include "editor/RayLayer.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "visibility/gl/GlShaders.h"
#include "glsl/layer_composite.frag.h"
#include "glsl/layer_composite.vert.h"

namespace sightline::ui {

namespace {

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/// Area of the convex hull of `points` (Andrew's monotone chain).
double hullArea(std::vector<glm::dvec2> points)
{
    std::sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) {
        return a.x < b.x || (a.x == b.x && a.y < b.y);
    });
    std::vector<glm::dvec2> hull(2 * points.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0)
            --k;
        hull[k++] = points[i];
    }
    for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0)
            --k;
        hull[k++] = points[i];
    }
    double twice = 0.0;
    for (std::size_t i = 0; i + 1 < k; ++i)
        twice += hull[i].x * hull[i + 1].y - hull[i + 1].x * hull[i].y;
    return 0.5 * std::abs(twice);
}

} // namespace

std::optional<BundleOnScreen> bundleOnScreen(const glm::mat4& viewProj, int width, int height, const Patch& source,
                                             const Patch& receiver)
{
    std::optional<glm::dvec2> failed;
    const auto toPixels = [&](const glm::dvec3& p) -> std::optional<glm::dvec2> {
        const glm::dvec4 clip = glm::dmat4(viewProj) * glm::dvec4(p, 1.0);
        if (clip.w <= 1e-9)
            return std::nullopt;
        return glm::dvec2((0.5 + 0.5 * clip.x / clip.w) * width, (0.5 + 0.5 * clip.y / clip.w) * height);
    };
    std::vector<glm::dvec2> corners;
    for (const Patch* patch : {&source, &receiver})
        for (int k = 0; k < 4; ++k) {
            const auto p = toPixels(patch->cornerPoint(k));
            if (!p)
                return std::nullopt;
            corners.push_back(*p);
        }
    const auto s = toPixels(source.centre()), r = toPixels(receiver.centre());
    if (!s || !r)
        return std::nullopt;
    BundleOnScreen bundle;
    bundle.min = bundle.max = corners.front();
    for (const glm::dvec2& c : corners) {
        bundle.min = glm::min(bundle.min, c);
        bundle.max = glm::max(bundle.max, c);
    }
    bundle.length = glm::length(*r - *s);
    bundle.area = hullArea(corners);
    return bundle;
}

double expectedOverlap(const BundleOnScreen& bundle, std::uint64_t rays)
{
    // A ray is at least a pixel wide, and the bundle at least one ray wide.
    const double length = std::max(bundle.length, 1.0);
    return double(rays) * length / std::max(bundle.area, length);
}

int rayLayerDivisor(double overlap) { return overlap <= 2.0 ? 1 : overlap <= 8.0 ? 2 : overlap <= 256.0 ? 4 : 8; }

float rayOpacity(double coverage, double overlap, int divisor)
{
    if (coverage >= 1.0)
        return 1.0f;
    if (coverage <= 0.0)
        return 0.0f;
    // A pixel of a layer `divisor` times coarser spans that many pixels across the bundle, so
    // about overlap x divisor rays cross it.
    const double perPixel = std::max(overlap * std::max(divisor, 1), 1e-9);
    const double a = 1.0 - std::pow(1.0 - coverage, 1.0 / perPixel);
    return float(std::min(a, coverage));
}

RayLayer::RayLayer(const gl::Functions& gl) : gl_(gl)
{
    program_ = gl::buildProgram(gl, {{GL_VERTEX_SHADER, glsl::layer_composite_vert}, {GL_FRAGMENT_SHADER, glsl::layer_composite_frag}},
                                "ray layer");
    gl.CreateVertexArrays(1, &vao_);   // attribute-less
}

RayLayer::~RayLayer()
{
    destroyTarget();
    gl_.DeleteProgram(program_);
    gl_.DeleteVertexArrays(1, &vao_);
}

void RayLayer::destroyTarget()
{
    if (framebuffer_)
        gl_.DeleteFramebuffers(1, &framebuffer_);
    if (coverage_)
        gl_.DeleteTextures(1, &coverage_);
    if (depth_)
        gl_.DeleteRenderbuffers(1, &depth_);
    framebuffer_ = coverage_ = depth_ = 0;
    width_ = height_ = 0;
}

bool RayLayer::begin(GLuint frame, int width, int height, int divisor, bool blocked)
{
    if (broken_)
        return false;
    const int w = std::max(1, (width + divisor - 1) / divisor), h = std::max(1, (height + divisor - 1) / divisor);
    if (w != width_ || h != height_ || blocked != blocked_) {
        destroyTarget();
        gl_.CreateFramebuffers(1, &framebuffer_);
        gl_.CreateTextures(GL_TEXTURE_2D, 1, &coverage_);
        gl_.TextureStorage2D(coverage_, 1, blocked ? GL_RG32F : GL_R32F, w, h);
        gl_.TextureParameteri(coverage_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        gl_.TextureParameteri(coverage_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        gl_.TextureParameteri(coverage_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        gl_.TextureParameteri(coverage_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        gl_.CreateRenderbuffers(1, &depth_);
        gl_.NamedRenderbufferStorage(depth_, GL_DEPTH24_STENCIL8, w, h);   // the frame's format: blits need it
        gl_.NamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, coverage_, 0);
        gl_.NamedFramebufferRenderbuffer(framebuffer_, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_);
        if (gl_.CheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            destroyTarget();
            broken_ = true;
            return false;
        }
        width_ = w;
        height_ = h;
        blocked_ = blocked;
    }
    while (gl_.GetError() != GL_NO_ERROR) {
    }
    // The frame's depth, each layer pixel taking one of the frame pixels it covers.
    gl_.BlitNamedFramebuffer(frame, framebuffer_, 0, 0, width, height, 0, 0, w, h, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    if (gl_.GetError() != GL_NO_ERROR) {
        broken_ = true;   // depth formats differ (a window's framebuffer): draw into the frame
        return false;
    }
    const float none[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    gl_.ClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, none);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    gl_.Viewport(0, 0, w, h);
    gl_.Enable(GL_BLEND);
    gl_.BlendFunc(GL_ONE, GL_ONE);
    return true;
}

void RayLayer::composite(GLuint frame, int width, int height, glm::dvec2 min, glm::dvec2 max, const glm::vec4& free,
                         const glm::vec4& blocked)
{
    gl_.BindFramebuffer(GL_FRAMEBUFFER, frame);
    gl_.Viewport(0, 0, width, height);
    gl_.Disable(GL_DEPTH_TEST);
    gl_.Enable(GL_BLEND);
    gl_.BlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    // A little margin: bilinear filtering spreads a layer pixel over its neighbours.
    const double margin = 8.0;
    min = glm::clamp(min - margin, glm::dvec2(0.0), glm::dvec2(width, height));
    max = glm::clamp(max + margin, glm::dvec2(0.0), glm::dvec2(width, height));
    if (max.x <= min.x || max.y <= min.y)
        return;
    const glm::vec2 lo(2.0 * min.x / width - 1.0, 2.0 * min.y / height - 1.0);
    const glm::vec2 hi(2.0 * max.x / width - 1.0, 2.0 * max.y / height - 1.0);
    gl_.ProgramUniform2f(program_, gl_.GetUniformLocation(program_, "lo"), lo.x, lo.y);
    gl_.ProgramUniform2f(program_, gl_.GetUniformLocation(program_, "hi"), hi.x, hi.y);
    gl_.ProgramUniform2f(program_, gl_.GetUniformLocation(program_, "frameSize"), float(width), float(height));
    const glm::vec3 freeRgb(free), blockedRgb(blocked);
    gl_.ProgramUniform3fv(program_, gl_.GetUniformLocation(program_, "freeColour"), 1, glm::value_ptr(freeRgb));
    gl_.ProgramUniform3fv(program_, gl_.GetUniformLocation(program_, "blockedColour"), 1, glm::value_ptr(blockedRgb));
    // An opaque ray (a = 1) covers its pixel alone: a large negative logarithm does the same.
    const auto log2Clear = [](float a) { return a >= 1.0f ? -64.0f : float(std::log2(1.0 - double(a))); };
    gl_.ProgramUniform2f(program_, gl_.GetUniformLocation(program_, "log2Clear"), log2Clear(free.a), log2Clear(blocked.a));
    gl_.UseProgram(program_);
    gl_.BindTextureUnit(0, coverage_);
    gl_.BindVertexArray(vao_);
    gl_.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
}

} // namespace sightline::ui
