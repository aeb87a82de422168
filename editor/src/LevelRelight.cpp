#include "editor/LevelRelight.h"

#include <string>

#include "visibility/gl/GlShaders.h"
#include "glsl/level_relight.frag.h"
#include "glsl/level_relight.vert.h"
#include "glsl/level_shading.glsl.h"

namespace sightline::ui {

namespace {

} // namespace

LevelRelight::LevelRelight(const gl::Functions& gl) : gl_(gl)
{
    program_ = gl::buildProgram(
        gl, {{GL_VERTEX_SHADER, glsl::level_relight_vert}, {GL_FRAGMENT_SHADER, std::string("#version 450 core\n") + glsl::level_shading_glsl + glsl::level_relight_frag}},
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
