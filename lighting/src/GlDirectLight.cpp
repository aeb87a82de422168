#include "lighting/GlDirectLight.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "lighting/LightEmission.h"
#include "base/Error.h"
#include "visibility/gl/GlShaders.h"
#include "glsl/lights_emitters.glsl.h"
#include "glsl/lights_map.frag.h"
#include "glsl/lights_map.geom.h"
#include "glsl/lights_map.vert.h"
#include "glsl/lights_shade.comp.h"

namespace sightline {

namespace {

// One emitter as the shaders read it (std430: five vec4s). Positions are relative to the scene's
// centre (the local origin keeps float precision at kilometre coordinates, docs/design.md §6).
//   position  xyz; w the type: 0 point, 1 spot, 2 directional, 3 area sample
//   direction spot and directional: the way the light travels; area: the unit normal m; w: two-sided
//   params    x intensity (point, spot, directional) or radiance A / (na nb) (area); y range (0: none);
//             z cos inner, w cos outer (spot)
//   colour    rgb; w the VPL clamp distance squared (area)
//   extra     x the light's index (its tile classes)
struct GpuEmitter {
    glm::vec4 position, direction, params, colour, extra;
};

GpuEmitter gpuEmitter(const Light& light, std::uint32_t index, const glm::dvec3& position, const glm::dvec3& origin)
{
    GpuEmitter g{};
    g.extra = glm::vec4(float(index), 0.0f, 0.0f, 0.0f);
    const glm::vec3 colour(light.colour);
    switch (light.type) {
    case LightType::Point:
    case LightType::Spot:
        g.position = glm::vec4(glm::vec3(position - origin), light.type == LightType::Point ? 0.0f : 1.0f);
        g.direction = glm::vec4(glm::vec3(light.direction), 0.0f);
        g.params = glm::vec4(float(light.intensity), float(light.range), float(std::cos(light.innerAngle)),
                             float(std::cos(light.outerAngle)));
        g.colour = glm::vec4(colour, 0.0f);
        break;
    case LightType::Directional:
        g.position = glm::vec4(0.0f, 0.0f, 0.0f, 2.0f);
        g.direction = glm::vec4(glm::vec3(light.direction), 0.0f);
        g.params = glm::vec4(float(light.intensity), 0.0f, 0.0f, 0.0f);
        g.colour = glm::vec4(colour, 0.0f);
        break;
    case LightType::Area: {
        const glm::dvec3 cross = glm::cross(light.area.u, light.area.v);
        const double area = glm::length(cross);
        g.position = glm::vec4(glm::vec3(position - origin), 3.0f);
        g.direction = glm::vec4(glm::vec3(cross / area), light.twoSided ? 1.0f : 0.0f);
        g.params = glm::vec4(float(light.radiance * area / double(light.area.sampleCount())), 0.0f, 0.0f, 0.0f);
        g.colour = glm::vec4(colour, float(light.clampMetres * light.clampMetres));
        break;
    }
    }
    return g;
}

double msSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

struct GlDirectLight::Impl {
    const gl::Functions& gl;
    GlDirectLightOptions options;
    glm::dvec3 origin{0.0};
    double radius = 1.0;
    GLsizei vertexCount = 0;
    GLuint vao = 0, vertexBuffer = 0, emitterBuffer = 0, pointBuffer = 0, irradianceBuffer = 0, bitBuffer = 0;
    GLuint batchBuffer = 0, classBuffer = 0, tileBuffer = 0;
    GLuint mapTexture = 0, framebuffer = 0, mapProgram = 0, shadeProgram = 0;
    int layers = 0;

    explicit Impl(const gl::Functions& functions) : gl(functions) {}
    ~Impl()
    {
        for (GLuint b : {vertexBuffer, emitterBuffer, pointBuffer, irradianceBuffer, bitBuffer, batchBuffer, classBuffer, tileBuffer})
            if (b)
                gl.DeleteBuffers(1, &b);
        if (vao)
            gl.DeleteVertexArrays(1, &vao);
        if (framebuffer)
            gl.DeleteFramebuffers(1, &framebuffer);
        if (mapTexture)
            gl.DeleteTextures(1, &mapTexture);
        for (GLuint p : {mapProgram, shadeProgram})
            if (p)
                gl.DeleteProgram(p);
    }

    void upload(GLuint& buffer, const void* data, std::size_t bytes) const
    {
        if (!buffer)
            gl.CreateBuffers(1, &buffer);
        gl.NamedBufferData(buffer, GLsizeiptr(std::max<std::size_t>(bytes, 16)), data, GL_DYNAMIC_DRAW);
    }

    /// One octahedral (or orthographic) map per emitter of `batch`, a layer each: the nearest
    /// blocker's distance, by min blending, both faces of every triangle drawn.
    void renderMaps(const GLint* batch, GLsizei count)
    {
        const float farthest[4] = {std::numeric_limits<float>::max(), 0.0f, 0.0f, 0.0f};
        upload(batchBuffer, batch, std::size_t(count) * sizeof(GLint));
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, batchBuffer);
        gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        gl.Viewport(0, 0, options.resolution, options.resolution);
        gl.Disable(GL_DEPTH_TEST);
        gl.Disable(GL_CULL_FACE);   // both faces of a triangle block
        for (GLenum plane : {GL_CLIP_DISTANCE0, GL_CLIP_DISTANCE1, GL_CLIP_DISTANCE2})
            gl.Enable(plane);
        gl.Enable(GL_BLEND);
        gl.BlendEquation(GL_MIN);
        gl.ClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, farthest);
        gl.UseProgram(mapProgram);
        gl.BindVertexArray(vao);
        if (vertexCount > 0)
            gl.DrawArraysInstanced(GL_TRIANGLES, 0, vertexCount, count);
        gl.Disable(GL_BLEND);
        gl.BlendEquation(GL_FUNC_ADD);
        for (GLenum plane : {GL_CLIP_DISTANCE0, GL_CLIP_DISTANCE1, GL_CLIP_DISTANCE2})
            gl.Disable(plane);
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        gl.Finish();
    }

    /// Adds the emitters of `batch` to every point's irradiance (their maps in the layers, or none
    /// for emitters settled by their tiles' classes).
    void shade(const GLint* batch, std::size_t count, std::size_t points)
    {
        upload(batchBuffer, batch, count * sizeof(GLint));
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, batchBuffer);
        gl.MemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        gl.UseProgram(shadeProgram);
        gl.ProgramUniform1i(shadeProgram, gl.GetUniformLocation(shadeProgram, "emitterCount"), GLint(count));
        gl.BindTextureUnit(0, mapTexture);
        // At most 65,535 groups a dispatch (the least GL guarantees).
        const std::size_t perDispatch = std::size_t(65535) * 64;
        for (std::size_t base = 0; base < points; base += perDispatch) {
            gl.ProgramUniform1i(shadeProgram, gl.GetUniformLocation(shadeProgram, "pointBase"), GLint(base));
            gl.DispatchCompute(GLuint((std::min(perDispatch, points - base) + 63) / 64), 1, 1);
        }
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        gl.Finish();
    }
};

namespace {

/// The tile classes packed four to a word for the shader; `partial` marks the lights with a
/// partial tile (the only ones that need maps).
std::vector<std::uint32_t> packClasses(const TileClasses& classes, std::vector<bool>& partial)
{
    std::vector<std::uint32_t> packed((classes.classes.size() + 3) / 4, 0u);
    for (std::size_t k = 0; k < classes.classes.size(); ++k) {
        packed[k / 4] |= std::uint32_t(classes.classes[k]) << (8 * (k % 4));
        if (classes.classes[k] == TileClass::Partial)
            partial[k % partial.size()] = true;
    }
    return packed;
}

} // namespace

GlDirectLight::GlDirectLight(const gl::Functions& gl, const WorldTriangles& triangles, GlDirectLightOptions options)
    : impl_(std::make_unique<Impl>(gl))
{
    Impl& m = *impl_;
    if (options.resolution < 16 || options.resolution > 8192)
        throw Error("GL lights: the shadow-map resolution must be in [16, 8192] (got " + std::to_string(options.resolution) + ")");
    m.options = options;
    if (!triangles.vertices.empty()) {
        glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (const glm::vec3& p : triangles.vertices) {
            lo = glm::min(lo, glm::dvec3(p));
            hi = glm::max(hi, glm::dvec3(p));
        }
        m.origin = 0.5 * (lo + hi);
        m.radius = 0.5 * glm::length(hi - lo) + 1.0;
    }
    std::vector<glm::vec3> local(triangles.vertices.size());
    for (std::size_t k = 0; k < local.size(); ++k)
        local[k] = glm::vec3(glm::dvec3(triangles.vertices[k]) - m.origin);
    m.vertexCount = GLsizei(local.size());

    const std::string emitters = std::string("#version 450 core\n") + glsl::lights_emitters_glsl;
    const std::string fragment = emitters + glsl::lights_map_frag;
    m.mapProgram = gl::buildProgram(gl, {{GL_VERTEX_SHADER, glsl::lights_map_vert}, {GL_GEOMETRY_SHADER, emitters + glsl::lights_map_geom},
                                         {GL_FRAGMENT_SHADER, fragment}},
                                    "GL lights shadow maps");
    m.shadeProgram = gl::buildProgram(gl, {{GL_COMPUTE_SHADER, emitters + glsl::lights_shade_comp}}, "GL lights shading");

    m.upload(m.vertexBuffer, local.data(), local.size() * sizeof(glm::vec3));
    m.vao = gl::positionVertexArray(gl, m.vertexBuffer);

    GLint maxLayers = 256;
    gl.GetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    const std::size_t mapBytes = std::size_t(options.resolution) * std::size_t(options.resolution) * sizeof(float);
    m.layers = int(std::clamp<std::size_t>(options.mapBytes / mapBytes, 1, std::size_t(std::max(maxLayers, 1))));
    gl.CreateTextures(GL_TEXTURE_2D_ARRAY, 1, &m.mapTexture);
    gl.TextureStorage3D(m.mapTexture, 1, GL_R32F, options.resolution, options.resolution, m.layers);
    gl.CreateFramebuffers(1, &m.framebuffer);
    gl.NamedFramebufferTexture(m.framebuffer, GL_COLOR_ATTACHMENT0, m.mapTexture, 0);   // layered
    const GLenum colour = GL_COLOR_ATTACHMENT0;
    gl.NamedFramebufferDrawBuffers(m.framebuffer, 1, &colour);
    if (gl.CheckNamedFramebufferStatus(m.framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("GL lights: the " + std::to_string(options.resolution) + "^2 x " + std::to_string(m.layers) +
                    " shadow-map framebuffer is incomplete");
}

GlDirectLight::~GlDirectLight() = default;

int GlDirectLight::resolution() const { return impl_->options.resolution; }

double GlDirectLight::texelAngle() const { return 3.0 * 2.0 / impl_->options.resolution; }

double GlDirectLight::directionalTexel() const { return 2.0 * impl_->radius / impl_->options.resolution; }

double GlDirectLight::bias(bool directional, double distance, double cosTheta) const
{
    const double lateral = directional ? directionalTexel() : distance * texelAngle();
    const double c = std::max(std::abs(cosTheta), 1e-6);
    const double tanTheta = std::sqrt(std::max(0.0, 1.0 - c * c)) / c;
    return lateral * std::min(1.0 + tanTheta, double(kGlLightMaxBiasTexels));
}

std::vector<glm::dvec3> GlDirectLight::irradiance(const std::vector<Light>& lights, std::span<const ShadingPoint> points,
                                                  GlDirectLightStats* stats, EmitterBits* bits, const TileClasses* classes)
{
    Impl& m = *impl_;
    const gl::Functions& gl = m.gl;
    const auto start = std::chrono::steady_clock::now();
    if (classes && (classes->tileOf.size() != points.size() || classes->lights != lights.size()))
        throw Error("GL lights: the tile classes were made for other points or lights");
    const std::vector<Emitter> emitters = lightEmitters(lights);
    std::vector<GpuEmitter> gpu;
    gpu.reserve(emitters.size());
    for (const Emitter& e : emitters)
        gpu.push_back(gpuEmitter(lights[e.light], e.light, e.position, m.origin));
    std::vector<glm::vec4> pointData(2 * points.size());
    for (std::size_t j = 0; j < points.size(); ++j) {
        pointData[2 * j] = glm::vec4(glm::vec3(points[j].position - m.origin), 1.0f);
        pointData[2 * j + 1] = glm::vec4(glm::vec3(points[j].normal), 0.0f);
    }
    // With classes, only the lights with a partial tile need maps; the others are shaded from
    // their classes alone.
    std::vector<bool> partial(lights.size(), classes == nullptr);
    const std::vector<std::uint32_t> packed = classes ? packClasses(*classes, partial) : std::vector<std::uint32_t>{};
    std::vector<GLint> mapped, unmapped;
    for (std::size_t e = 0; e < emitters.size(); ++e)
        (partial[emitters[e].light] ? mapped : unmapped).push_back(GLint(e));

    const std::size_t words = (emitters.size() + 31) / 32;
    m.upload(m.emitterBuffer, gpu.data(), gpu.size() * sizeof(GpuEmitter));
    m.upload(m.pointBuffer, pointData.data(), pointData.size() * sizeof(glm::vec4));
    const std::vector<glm::vec4> zeros(points.size(), glm::vec4(0.0f));
    m.upload(m.irradianceBuffer, zeros.data(), zeros.size() * sizeof(glm::vec4));
    std::vector<std::uint32_t> bitWords(bits ? points.size() * words : 0, 0u);
    m.upload(m.bitBuffer, bitWords.data(), bitWords.size() * sizeof(std::uint32_t));
    m.upload(m.classBuffer, packed.data(), packed.size() * sizeof(std::uint32_t));
    m.upload(m.tileBuffer, classes ? classes->tileOf.data() : nullptr, classes ? classes->tileOf.size() * sizeof(std::uint32_t) : 0);

    const GLuint mp = m.mapProgram, sp = m.shadeProgram;
    gl.ProgramUniform1f(mp, gl.GetUniformLocation(mp, "invRadius"), float(1.0 / m.radius));
    gl.ProgramUniform1f(sp, gl.GetUniformLocation(sp, "invRadius"), float(1.0 / m.radius));
    gl.ProgramUniform1f(sp, gl.GetUniformLocation(sp, "texelAngle"), float(texelAngle()));
    gl.ProgramUniform1f(sp, gl.GetUniformLocation(sp, "directionalTexel"), float(directionalTexel()));
    gl.ProgramUniform1f(sp, gl.GetUniformLocation(sp, "maxBiasTexels"), kGlLightMaxBiasTexels);
    gl.ProgramUniform1i(sp, gl.GetUniformLocation(sp, "resolution"), m.options.resolution);
    gl.ProgramUniform1i(sp, gl.GetUniformLocation(sp, "pointCount"), GLint(points.size()));
    gl.ProgramUniform1i(sp, gl.GetUniformLocation(sp, "wantBits"), bits ? 1 : 0);
    gl.ProgramUniform1i(sp, gl.GetUniformLocation(sp, "wordsPerPoint"), GLint(words));
    gl.ProgramUniform1i(sp, gl.GetUniformLocation(sp, "useClasses"), classes ? 1 : 0);
    gl.ProgramUniform1i(sp, gl.GetUniformLocation(sp, "lightCount"), GLint(lights.size()));
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m.emitterBuffer);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m.pointBuffer);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m.irradianceBuffer);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, m.bitBuffer);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, m.classBuffer);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, m.tileBuffer);

    GlDirectLightStats s;
    s.lights = lights.size();
    s.emitters = emitters.size();
    s.maps = mapped.size();
    s.points = points.size();
    s.triangles = std::size_t(m.vertexCount) / 3;
    const auto shade = [&](const GLint* batch, std::size_t count) {
        const auto phase = std::chrono::steady_clock::now();
        m.shade(batch, count, points.size());
        s.shadeMs += msSince(phase);
    };
    for (std::size_t first = 0; first < mapped.size(); first += std::size_t(m.layers)) {
        const GLsizei count = GLsizei(std::min<std::size_t>(std::size_t(m.layers), mapped.size() - first));
        ++s.batches;
        const auto phase = std::chrono::steady_clock::now();
        m.renderMaps(&mapped[first], count);
        s.renderMs += msSince(phase);
        shade(&mapped[first], std::size_t(count));
    }
    if (!unmapped.empty())
        shade(unmapped.data(), unmapped.size());   // every tile settled by its class: no map is read
    const auto readStart = std::chrono::steady_clock::now();
    gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> sums(points.size());
    if (!points.empty())
        gl.GetNamedBufferSubData(m.irradianceBuffer, 0, GLsizeiptr(sums.size() * sizeof(glm::vec4)), sums.data());
    if (bits) {
        if (!bitWords.empty())
            gl.GetNamedBufferSubData(m.bitBuffer, 0, GLsizeiptr(bitWords.size() * sizeof(std::uint32_t)), bitWords.data());
        *bits = EmitterBits(points.size(), emitters.size());
        bits->bits = std::move(bitWords);
    }
    if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
        throw Error("GL lights: OpenGL error " + std::to_string(error) + " while shading");
    s.shadeMs += msSince(readStart);
    std::vector<glm::dvec3> out(points.size());
    for (std::size_t j = 0; j < points.size(); ++j)
        out[j] = glm::dvec3(sums[j]);
    s.ms = msSince(start);
    if (stats)
        *stats = s;
    return out;
}

} // namespace sightline
