#include "visibility/HeckbertHerfSampler.h"

#include <chrono>
#include <cmath>
#include <string>

#include <glm/mat4x4.hpp>

#include "visibility/gl/GlShaders.h"
#include "base/Error.h"
#include "visibility/ShaftGeometry.h"
#include "glsl/hh_count.frag.h"
#include "glsl/hh_projection.vert.h"

namespace sightline {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

/// How far short of the source sample the counted part of the segment stops, as a fraction of the
/// way (a baseline that counts only; the exact samplers use ExactSegment.h's margin).
constexpr double kNear = 1e-6;

} // namespace

struct HeckbertHerfSampler::Impl {
    const gl::Functions& gl;
    WorldTriangles triangles;
    GLuint program = 0, vertexArray = 0, buffer = 0;
    GLuint framebuffer = 0, counts = 0, stencil = 0;
    int width = 0, height = 0;

    Impl(const gl::Functions& functions, WorldTriangles tris) : gl(functions), triangles(std::move(tris)) {}
    ~Impl()
    {
        releaseTarget();
        if (program)
            gl.DeleteProgram(program);
        gl.DeleteBuffers(1, &buffer);
        gl.DeleteVertexArrays(1, &vertexArray);
    }

    void releaseTarget()
    {
        if (framebuffer) {
            gl.DeleteFramebuffers(1, &framebuffer);
            gl.DeleteTextures(1, &counts);
            gl.DeleteRenderbuffers(1, &stencil);
        }
        framebuffer = counts = stencil = 0;
    }

    void ensureTarget(int w, int h)
    {
        if (framebuffer && w == width && h == height)
            return;
        releaseTarget();
        gl.CreateFramebuffers(1, &framebuffer);
        gl.CreateTextures(GL_TEXTURE_2D, 1, &counts);
        gl.TextureStorage2D(counts, 1, GL_R32F, w, h);   // exact integers up to 2^24
        gl.CreateRenderbuffers(1, &stencil);
        gl.NamedRenderbufferStorage(stencil, GL_DEPTH24_STENCIL8, w, h);
        gl.NamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, counts, 0);
        gl.NamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, stencil);
        const GLenum buffers[1] = {GL_COLOR_ATTACHMENT0};
        gl.NamedFramebufferDrawBuffers(framebuffer, 1, buffers);
        if (gl.CheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw Error("Heckbert-Herf sampler: incomplete framebuffer of " + std::to_string(w) + "x" + std::to_string(h));
        width = w;
        height = h;
    }
};

HeckbertHerfSampler::HeckbertHerfSampler(const gl::Functions& gl, WorldTriangles triangles)
    : impl_(std::make_unique<Impl>(gl, std::move(triangles)))
{
    impl_->program = gl::buildProgram(gl, {{GL_VERTEX_SHADER, glsl::hh_projection_vert}, {GL_FRAGMENT_SHADER, glsl::hh_count_frag}},
                                      "Heckbert-Herf sampler");
    gl.CreateBuffers(1, &impl_->buffer);
    impl_->vertexArray = gl::positionVertexArray(gl, impl_->buffer);
}

HeckbertHerfSampler::~HeckbertHerfSampler() = default;

std::vector<std::uint32_t> HeckbertHerfSampler::blockedCounts(const Patch& source, const Patch& receiver,
                                                              HeckbertHerfStats* stats)
{
    validatePatchPair(source, receiver);
    const gl::Functions& gl = impl_->gl;
    const auto setupStart = Clock::now();

    // The triangles that can meet the shaft, uploaded for this pair.
    const ShaftHull hull(source, receiver);
    std::vector<glm::vec3> kept;
    const std::vector<glm::vec3>& all = impl_->triangles.vertices;
    for (std::size_t i = 0; i + 2 < all.size(); i += 3)
        if (!hull.excludes(all[i], all[i + 1], all[i + 2]))
            kept.insert(kept.end(), all.begin() + std::ptrdiff_t(i), all.begin() + std::ptrdiff_t(i + 3));
    gl.NamedBufferData(impl_->buffer, GLsizeiptr(kept.size() * sizeof(glm::vec3)), kept.data(), GL_STREAM_DRAW);
    impl_->ensureTarget(receiver.na, receiver.nb);
    const float zero[4] = {0, 0, 0, 0};
    gl.ClearNamedFramebufferfv(impl_->framebuffer, GL_COLOR, 0, zero);
    const PatchFrame frame(receiver, source.centre());   // (X, Y, D), D > 0 towards the source
    const GLint projection = gl.GetUniformLocation(impl_->program, "uProjection");
    const GLint depthRow = gl.GetUniformLocation(impl_->program, "uDepth");
    gl.ProgramUniform1f(impl_->program, gl.GetUniformLocation(impl_->program, "uNear"), float(kNear));
    const double setupMs = msSince(setupStart);

    const auto drawStart = Clock::now();
    gl.BindFramebuffer(GL_FRAMEBUFFER, impl_->framebuffer);
    gl.Viewport(0, 0, receiver.na, receiver.nb);
    gl.UseProgram(impl_->program);
    gl.BindVertexArray(impl_->vertexArray);
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_ONE, GL_ONE);
    gl.Enable(GL_STENCIL_TEST);
    gl.StencilFunc(GL_EQUAL, 0, 0xff);        // each pixel counts once per render
    gl.StencilOp(GL_KEEP, GL_KEEP, GL_INCR);
    gl.Enable(GL_CLIP_DISTANCE0);
    gl.Enable(GL_CLIP_DISTANCE1);
    for (int i = 0; i < source.sampleCount() && !kept.empty(); ++i) {
        const glm::dvec3 s = frame.coordinates(source.sample(i));
        // Rows of the world -> clip map, each an affine function of (X, Y, D), which are affine
        // in the world point: row = fX X + fY Y + fD D + c.
        auto row = [&](double fX, double fY, double fD, double c) {
            const glm::dvec3 axis = fX * frame.sAxis + fY * frame.tAxis + fD * frame.dAxis;
            return glm::dvec4(axis, c - glm::dot(axis, frame.origin));
        };
        const glm::dvec4 x = row(2.0, 0.0, (1.0 - 2.0 * s.x) / s.z, -1.0);
        const glm::dvec4 y = row(0.0, 2.0, (1.0 - 2.0 * s.y) / s.z, -1.0);
        const glm::dvec4 w = row(0.0, 0.0, -1.0 / s.z, 1.0);
        const glm::vec4 depth(row(0.0, 0.0, 1.0 / s.z, 0.0));
        glm::mat4 m;   // column-major: m[column][row]; z = 0, inside the clip volume for any w > 0
        for (int c = 0; c < 4; ++c)
            m[c] = glm::vec4(float(x[c]), float(y[c]), 0.0f, float(w[c]));
        gl.ProgramUniformMatrix4fv(impl_->program, projection, 1, GL_FALSE, &m[0][0]);
        gl.ProgramUniform4fv(impl_->program, depthRow, 1, &depth.x);
        gl.ClearNamedFramebufferfi(impl_->framebuffer, GL_DEPTH_STENCIL, 0, 1.0f, 0);
        gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(kept.size()));
    }
    gl.Finish();
    gl.Disable(GL_STENCIL_TEST);
    gl.Disable(GL_CLIP_DISTANCE0);
    gl.Disable(GL_CLIP_DISTANCE1);
    gl.Disable(GL_BLEND);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    const double drawMs = msSince(drawStart);

    const auto readStart = Clock::now();
    std::vector<float> pixels(std::size_t(receiver.na) * std::size_t(receiver.nb));
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl.GetTextureImage(impl_->counts, 0, GL_RED, GL_FLOAT, GLsizei(pixels.size() * sizeof(float)), pixels.data());
    if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
        throw Error("Heckbert-Herf sampler: OpenGL error " + std::to_string(error));
    std::vector<std::uint32_t> out(pixels.size());
    for (std::size_t j = 0; j < pixels.size(); ++j)
        out[j] = std::uint32_t(std::lround(pixels[j]));
    if (stats)
        *stats = {setupMs, drawMs, msSince(readStart), kept.size() / 3};
    return out;
}

} // namespace sightline
