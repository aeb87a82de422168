#include "lighting/ao/AoGlCaster.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <meshoptimizer.h>

#include "base/Error.h"
#include "visibility/gl/GlShaders.h"
#include "glsl/ao_compare.comp.h"
#include "glsl/ao_depth.frag.h"
#include "glsl/ao_depth.vert.h"

namespace sightline {

namespace {

void basisOf(const glm::vec3& d, glm::vec3& u, glm::vec3& v)
{
    const glm::vec3 helper = std::abs(d.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    u = glm::normalize(glm::cross(helper, d));
    v = glm::cross(d, u);
}

} // namespace

struct AoGlCaster::Impl {
    const gl::Functions& gl;
    AoGlOptions options;
    glm::vec3 centre{0.0f};
    float radius = 1.0f;
    GLsizei indexCount = 0;
    double simplificationError = 0.0;   ///< metres
    GLuint vao = 0, vertexBuffer = 0, indexBuffer = 0, depthTexture = 0, framebuffer = 0;
    GLuint depthProgram = 0, compareProgram = 0;
    GLuint originBuffer = 0, normalBuffer = 0, bitBuffer = 0;

    explicit Impl(const gl::Functions& functions) : gl(functions) {}
    ~Impl()
    {
        GLuint buffers[] = {vertexBuffer, indexBuffer, originBuffer, normalBuffer, bitBuffer};
        for (GLuint b : buffers)
            if (b)
                gl.DeleteBuffers(1, &b);
        if (vao)
            gl.DeleteVertexArrays(1, &vao);
        if (framebuffer)
            gl.DeleteFramebuffers(1, &framebuffer);
        if (depthTexture)
            gl.DeleteTextures(1, &depthTexture);
        if (depthProgram)
            gl.DeleteProgram(depthProgram);
        if (compareProgram)
            gl.DeleteProgram(compareProgram);
    }

    void setFrame(GLuint program, const glm::vec3& u, const glm::vec3& v, const glm::vec3& d) const
    {
        gl.ProgramUniform3fv(program, gl.GetUniformLocation(program, "centre"), 1, &centre.x);
        gl.ProgramUniform3fv(program, gl.GetUniformLocation(program, "axisU"), 1, &u.x);
        gl.ProgramUniform3fv(program, gl.GetUniformLocation(program, "axisV"), 1, &v.x);
        gl.ProgramUniform3fv(program, gl.GetUniformLocation(program, "axisD"), 1, &d.x);
        gl.ProgramUniform1f(program, gl.GetUniformLocation(program, "invRadius"), 1.0f / radius);
    }
};

AoGlCaster::AoGlCaster(const gl::Functions& gl, const AoOccluders& occluders, AoGlOptions options)
    : impl_(std::make_unique<Impl>(gl))
{
    Impl& m = *impl_;
    m.options = options;
    if (!occluders.bounds.empty())
        m.centre = (occluders.bounds.min + occluders.bounds.max) * 0.5f;
    double radius = 0.0;
    for (const glm::vec3& p : occluders.vertices)
        radius = std::max(radius, double(glm::length(p - m.centre)));
    m.radius = float(radius * 1.01 + 1e-6);
    m.depthProgram = gl::buildProgram(gl, {{GL_VERTEX_SHADER, glsl::ao_depth_vert}, {GL_FRAGMENT_SHADER, glsl::ao_depth_frag}}, "GL AO depth map");
    m.compareProgram = gl::buildProgram(gl, {{GL_COMPUTE_SHADER, glsl::ao_compare_comp}}, "GL AO depth compare");

    // Coarse occluders where they give the same answer: edge collapses that move the surface by
    // less than a fraction of a texel, which the compare's bias (at least a texel) and the map's
    // resolution already cover. meshoptimizer measures the error relative to the mesh's scale.
    std::vector<std::uint32_t> indices = occluders.indices;
    if (options.simplifyTexels > 0.0 && !indices.empty()) {
        const float scale = meshopt_simplifyScale(&occluders.vertices[0].x, occluders.vertices.size(), sizeof(glm::vec3));
        if (scale > 0.0f) {
            const double limit = options.simplifyTexels * 2.0 * double(m.radius) / options.resolution;
            float error = 0.0f;
            indices.resize(meshopt_simplify(indices.data(), occluders.indices.data(), occluders.indices.size(),
                                            &occluders.vertices[0].x, occluders.vertices.size(), sizeof(glm::vec3), 0,
                                            float(limit / scale), 0, &error));
            m.simplificationError = double(error) * scale;
        }
    }
    gl.CreateBuffers(1, &m.vertexBuffer);
    gl.NamedBufferData(m.vertexBuffer, GLsizeiptr(occluders.vertices.size() * sizeof(glm::vec3)), occluders.vertices.data(),
                       GL_STATIC_DRAW);
    gl.CreateBuffers(1, &m.indexBuffer);
    gl.NamedBufferData(m.indexBuffer, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(), GL_STATIC_DRAW);
    m.indexCount = GLsizei(indices.size());
    m.vao = gl::positionVertexArray(gl, m.vertexBuffer);
    gl.VertexArrayElementBuffer(m.vao, m.indexBuffer);

    gl.CreateTextures(GL_TEXTURE_2D, 1, &m.depthTexture);
    gl.TextureStorage2D(m.depthTexture, 1, GL_RG32F, options.resolution, options.resolution);
    gl.CreateFramebuffers(1, &m.framebuffer);
    gl.NamedFramebufferTexture(m.framebuffer, GL_COLOR_ATTACHMENT0, m.depthTexture, 0);
    const GLenum colour = GL_COLOR_ATTACHMENT0;
    gl.NamedFramebufferDrawBuffers(m.framebuffer, 1, &colour);
    if (gl.CheckNamedFramebufferStatus(m.framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("GL AO: the " + std::to_string(options.resolution) + "^2 depth-pair framebuffer is incomplete");
}

AoGlCaster::~AoGlCaster() = default;

double AoGlCaster::texelSize() const { return 2.0 * impl_->radius / impl_->options.resolution; }

std::size_t AoGlCaster::drawnTriangles() const { return std::size_t(impl_->indexCount) / 3; }

double AoGlCaster::simplificationError() const { return impl_->simplificationError; }

double AoGlCaster::bias(double cosTheta) const
{
    const double tanTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta)) / cosTheta;
    return texelSize() * std::min(1.0 + tanTheta, double(kAoGlMaxBiasTexels));
}

bool AoGlCaster::fill(const AoPoints& points, const AoDirectionSet& set, int first, int last, VisibilityMatrix& matrix,
                      const AoFillControl& control)
{
    Impl& m = *impl_;
    const gl::Functions& gl = m.gl;
    if (first >= last || points.size() == 0)
        return true;
    const int words32 = matrix.words() * 2;
    std::vector<glm::vec4> origins(points.size()), normals(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        origins[i] = glm::vec4(points.origins[i], 1.0f);
        normals[i] = glm::vec4(points.normals[i], 0.0f);
    }
    auto upload = [&](GLuint& buffer, const void* data, std::size_t bytes) {
        if (!buffer)
            gl.CreateBuffers(1, &buffer);
        gl.NamedBufferData(buffer, GLsizeiptr(bytes), data, GL_DYNAMIC_DRAW);
    };
    upload(m.originBuffer, origins.data(), origins.size() * sizeof(glm::vec4));
    upload(m.normalBuffer, normals.data(), normals.size() * sizeof(glm::vec4));
    std::vector<std::uint32_t> bits(points.size() * std::size_t(words32), 0u);
    upload(m.bitBuffer, bits.data(), bits.size() * sizeof(std::uint32_t));

    const GLuint cp = m.compareProgram;
    gl.ProgramUniform1f(cp, gl.GetUniformLocation(cp, "texelWorld"), float(texelSize()));
    gl.ProgramUniform1f(cp, gl.GetUniformLocation(cp, "maxBiasTexels"), kAoGlMaxBiasTexels);
    gl.ProgramUniform1i(cp, gl.GetUniformLocation(cp, "resolution"), m.options.resolution);
    gl.ProgramUniform1i(cp, gl.GetUniformLocation(cp, "pointCount"), GLint(points.size()));
    gl.ProgramUniform1i(cp, gl.GetUniformLocation(cp, "wordsPerPoint"), words32);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m.originBuffer);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m.normalBuffer);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m.bitBuffer);

    bool cancelled = false;
    const GLint positiveLocation = gl.GetUniformLocation(cp, "directionPos");
    const GLint negativeLocation = gl.GetUniformLocation(cp, "directionNeg");
    const float farthest[4] = {2.0f, 2.0f, 2.0f, 2.0f};   // beyond the bounding sphere's [-1, 1]
    for (int j = first; j < last; ++j) {
        const int a = set.antipode[std::size_t(j)];
        const bool pair = a >= first && a < last;
        if (pair && a < j)
            continue;   // answered with its antipode
        if (control.cancelled()) {
            cancelled = true;
            break;
        }
        // The pair is always rendered from its lower index's side, so a direction gets the same
        // texels, and bits, whether its antipode is filled in the same call or not.
        const int positive = std::min(j, a), negative = std::max(j, a);
        glm::vec3 u, v;
        const glm::vec3 d = set.directions[std::size_t(positive)];
        basisOf(d, u, v);
        // Pass 1 (§3.2): the scene's nearest surfaces towards d and -d, orthographic.
        gl.BindFramebuffer(GL_FRAMEBUFFER, m.framebuffer);
        gl.Viewport(0, 0, m.options.resolution, m.options.resolution);
        gl.Disable(GL_DEPTH_TEST);
        gl.Disable(GL_CULL_FACE);   // both faces of a triangle block
        gl.Enable(GL_BLEND);
        gl.BlendEquation(GL_MIN);
        gl.ClearNamedFramebufferfv(m.framebuffer, GL_COLOR, 0, farthest);
        gl.UseProgram(m.depthProgram);
        m.setFrame(m.depthProgram, u, v, d);
        gl.BindVertexArray(m.vao);
        gl.DrawElements(GL_TRIANGLES, m.indexCount, GL_UNSIGNED_INT, nullptr);
        gl.Disable(GL_BLEND);
        gl.BlendEquation(GL_FUNC_ADD);
        // Pass 2: every point's depth against the map, bits set in the shader.
        gl.MemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        gl.UseProgram(cp);
        m.setFrame(cp, u, v, d);
        gl.ProgramUniform1i(cp, positiveLocation, positive >= first && positive < last ? positive : -1);
        gl.ProgramUniform1i(cp, negativeLocation, negative >= first && negative < last ? negative : -1);
        gl.BindTextureUnit(0, m.depthTexture);
        gl.DispatchCompute(GLuint((points.size() + 63) / 64), 1, 1);
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        control.finishedOne();
        if (pair)
            control.finishedOne();
    }
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl.GetNamedBufferSubData(m.bitBuffer, 0, GLsizeiptr(bits.size() * sizeof(std::uint32_t)), bits.data());
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::uint64_t* row = matrix.row(i);
        for (int w = 0; w < matrix.words(); ++w)
            row[w] |= std::uint64_t(bits[i * std::size_t(words32) + std::size_t(2 * w)]) |
                      (std::uint64_t(bits[i * std::size_t(words32) + std::size_t(2 * w + 1)]) << 32);
    }
    if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
        throw Error("GL AO: OpenGL error " + std::to_string(error) + " while filling the visibility matrix");
    return !cancelled;
}

} // namespace sightline
