#include "LevelRelight.h"

#include <string>

#include "visibility/gl/GlShaders.h"

namespace sightline::ui {

const char* const kLevelShadingGlsl = R"(
uniform int aoOn;            // ambient occlusion from the light map (AoPreview.h)
uniform int litOn;           // the lit view: the light map is the light (LitPreview.h)
layout(binding = 3) uniform sampler2D aoMap;
vec3 shadeLevel(vec3 c, float light, vec2 mapUv) {
    // The map has one level: an explicit lod keeps the relight pass's reads equal to the draw's.
    if (litOn != 0 && aoOn != 0) {
        // A faint headlight keeps unlit geometry readable; texels outside the map stay dark.
        vec3 lit = mapUv.x >= 0.0 ? textureLod(aoMap, mapUv, 0.0).rgb : vec3(0.0);
        return c * (0.06 * light + 1.25 * lit);
    }
    vec3 ambient = vec3(1.0);
    if (aoOn != 0 && mapUv.x >= 0.0)   // a floor, so the darkest corner still reads; HDR light clamped
        ambient = 0.3 + 0.7 * min(textureLod(aoMap, mapUv, 0.0).rgb, vec3(1.5));
    return c * light * ambient;
}
)";

namespace {

const char* kRelightVertex = R"(#version 450 core
void main() {   // one triangle over the whole target
    vec2 p = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
}
)";

const char* kRelightFragment = R"(
layout(binding = 6) uniform sampler2D surfaceMap;   // (map uv, headlight, 1 where the map shades it)
layout(binding = 7) uniform sampler2D baseMap;      // the colour before light
layout(location = 0) out vec4 colour;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 s = texelFetch(surfaceMap, p, 0);
    if (s.w == 0.0) discard;   // background, wireframe, or drawn without the map: kept
    colour = vec4(shadeLevel(texelFetch(baseMap, p, 0).rgb, s.z, s.xy), 1.0);
}
)";

} // namespace

LevelRelight::LevelRelight(const gl::Functions& gl) : gl_(gl)
{
    program_ = gl::buildProgram(
        gl, {{GL_VERTEX_SHADER, kRelightVertex}, {GL_FRAGMENT_SHADER, std::string("#version 450 core\n") + kLevelShadingGlsl + kRelightFragment}},
        "viewport relight");
    gl.ProgramUniform1i(program_, gl.GetUniformLocation(program_, "aoOn"), 1);
    gl.CreateVertexArrays(1, &vertexArray_);
}

LevelRelight::~LevelRelight()
{
    release();
    gl_.DeleteVertexArrays(1, &vertexArray_);
    gl_.DeleteProgram(program_);
}

void LevelRelight::release()
{
    if (relightFramebuffer_)
        gl_.DeleteFramebuffers(1, &relightFramebuffer_);
    GLuint textures[] = {surface_, base_};
    gl_.DeleteTextures(2, textures);
    surface_ = base_ = relightFramebuffer_ = framebuffer_ = 0;
    width_ = height_ = 0;
    writing_ = false;
}

bool LevelRelight::attach(GLuint framebuffer, GLuint colour, int width, int height)
{
    release();
    framebuffer_ = framebuffer;
    width_ = width;
    height_ = height;
    // 32-bit floats: the pass reads back exactly what the draw's shading had.
    for (GLuint* texture : {&surface_, &base_}) {
        gl_.CreateTextures(GL_TEXTURE_2D, 1, texture);
        gl_.TextureStorage2D(*texture, 1, GL_RGBA32F, width, height);
    }
    gl_.NamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT1, surface_, 0);
    gl_.NamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT2, base_, 0);
    gl_.CreateFramebuffers(1, &relightFramebuffer_);
    gl_.NamedFramebufferRenderbuffer(relightFramebuffer_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
    setWriting(false);
    return gl_.CheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE &&
           gl_.CheckNamedFramebufferStatus(relightFramebuffer_, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

void LevelRelight::setWriting(bool on)
{
    if (!framebuffer_)
        return;
    const GLenum all[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    gl_.NamedFramebufferDrawBuffers(framebuffer_, on ? 3 : 1, all);
    writing_ = on;
}

void LevelRelight::clear()
{
    if (!framebuffer_)
        return;
    const float none[4] = {-1.0f, -1.0f, 0.0f, 0.0f};
    gl_.ClearTexImage(surface_, 0, GL_RGBA, GL_FLOAT, none);
}

void LevelRelight::relight(bool lit)
{
    gl_.ProgramUniform1i(program_, gl_.GetUniformLocation(program_, "litOn"), lit ? 1 : 0);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, relightFramebuffer_);
    gl_.Viewport(0, 0, width_, height_);
    gl_.Disable(GL_DEPTH_TEST);
    gl_.UseProgram(program_);
    gl_.BindTextureUnit(6, surface_);
    gl_.BindTextureUnit(7, base_);
    gl_.BindVertexArray(vertexArray_);
    gl_.DrawArrays(GL_TRIANGLES, 0, 3);
    gl_.Enable(GL_DEPTH_TEST);
}

} // namespace sightline::ui
