#pragma once
// The OpenGL 4.5 core entry points Sightline uses, resolved from whatever context is current.
//
// One GL code path serves the editor's Qt context, OSMesa and EGL (docs/design.md §1): the caller hands
// in its context's getProcAddress (QOpenGLContext::getProcAddress, OSMesaGetProcAddress,
// eglGetProcAddress) and the samplers call through this table. A small table rather than a loader
// library because none in Debian takes a caller's resolver: libepoxy and glbinding 2 look symbols
// up in libGL themselves, which is wrong under OSMesa.

#include <string>

#include <GL/glcorearb.h>

namespace sightline::gl {

// Qt's headers may include <GL/gl.h> before this file, which defines GL_VERSION_1_1 and so hides
// glcorearb.h's typedefs of the OpenGL 1.1 entry points: those are named here.
using PfnDeleteTextures = void(APIENTRYP)(GLsizei n, const GLuint* textures);
using PfnDrawArrays = void(APIENTRYP)(GLenum mode, GLint first, GLsizei count);
using PfnDrawElements = void(APIENTRYP)(GLenum mode, GLsizei count, GLenum type, const void* indices);
using PfnPolygonOffset = void(APIENTRYP)(GLfloat factor, GLfloat units);

#define SIGHTLINE_GL_FUNCTIONS(X)                                                                  \
    X(PFNGLGETSTRINGPROC, GetString)                                                               \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                           \
    X(PFNGLGETERRORPROC, GetError)                                                                 \
    X(PFNGLCREATESHADERPROC, CreateShader)                                                         \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                         \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                                                       \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                           \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                                 \
    X(PFNGLDELETESHADERPROC, DeleteShader)                                                         \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                                       \
    X(PFNGLATTACHSHADERPROC, AttachShader)                                                         \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                           \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                         \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                               \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                                       \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                                                             \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                             \
    X(PFNGLPROGRAMUNIFORM2IPROC, ProgramUniform2i)                                                 \
    X(PFNGLPROGRAMUNIFORM1FPROC, ProgramUniform1f)                                                 \
    X(PFNGLPROGRAMUNIFORM1UIPROC, ProgramUniform1ui)                                               \
    X(PFNGLPROGRAMUNIFORM3FVPROC, ProgramUniform3fv)                                               \
    X(PFNGLPROGRAMUNIFORM4FVPROC, ProgramUniform4fv)                                               \
    X(PFNGLCREATEVERTEXARRAYSPROC, CreateVertexArrays)                                             \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                             \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                                   \
    X(PFNGLVERTEXARRAYVERTEXBUFFERPROC, VertexArrayVertexBuffer)                                   \
    X(PFNGLVERTEXARRAYATTRIBFORMATPROC, VertexArrayAttribFormat)                                   \
    X(PFNGLVERTEXARRAYATTRIBBINDINGPROC, VertexArrayAttribBinding)                                 \
    X(PFNGLENABLEVERTEXARRAYATTRIBPROC, EnableVertexArrayAttrib)                                   \
    X(PFNGLCREATEBUFFERSPROC, CreateBuffers)                                                       \
    X(PFNGLNAMEDBUFFERDATAPROC, NamedBufferData)                                                   \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                                       \
    X(PFNGLCREATETEXTURESPROC, CreateTextures)                                                     \
    X(PFNGLTEXTURESTORAGE2DPROC, TextureStorage2D)                                                 \
    X(PFNGLTEXTURESTORAGE3DPROC, TextureStorage3D)                                                 \
    X(PFNGLGETTEXTUREIMAGEPROC, GetTextureImage)                                                   \
    X(PFNGLCLEARTEXIMAGEPROC, ClearTexImage)                                                       \
    X(PfnDeleteTextures, DeleteTextures)                                                            \
    X(PFNGLCREATEFRAMEBUFFERSPROC, CreateFramebuffers)                                             \
    X(PFNGLNAMEDFRAMEBUFFERTEXTUREPROC, NamedFramebufferTexture)                                   \
    X(PFNGLNAMEDFRAMEBUFFERDRAWBUFFERSPROC, NamedFramebufferDrawBuffers)                           \
    X(PFNGLCHECKNAMEDFRAMEBUFFERSTATUSPROC, CheckNamedFramebufferStatus)                           \
    X(PFNGLCLEARNAMEDFRAMEBUFFERUIVPROC, ClearNamedFramebufferuiv)                                 \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                             \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                                   \
    X(PFNGLVIEWPORTPROC, Viewport)                                                                 \
    X(PFNGLENABLEPROC, Enable)                                                                     \
    X(PFNGLDISABLEPROC, Disable)                                                                   \
    X(PFNGLLOGICOPPROC, LogicOp)                                                                   \
    X(PfnDrawArrays, DrawArrays)                                                                    \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                           \
    X(PFNGLFINISHPROC, Finish)                                                                     \
    X(PFNGLPROGRAMUNIFORMMATRIX4FVPROC, ProgramUniformMatrix4fv)                                   \
    X(PFNGLSTENCILFUNCPROC, StencilFunc)                                                           \
    X(PFNGLSTENCILOPPROC, StencilOp)                                                               \
    X(PFNGLBLENDFUNCPROC, BlendFunc)                                                               \
    X(PFNGLCLEARNAMEDFRAMEBUFFERFVPROC, ClearNamedFramebufferfv)                                   \
    X(PFNGLCLEARNAMEDFRAMEBUFFERFIPROC, ClearNamedFramebufferfi)                                   \
    X(PFNGLCREATERENDERBUFFERSPROC, CreateRenderbuffers)                                           \
    X(PFNGLNAMEDRENDERBUFFERSTORAGEPROC, NamedRenderbufferStorage)                                 \
    X(PFNGLNAMEDFRAMEBUFFERRENDERBUFFERPROC, NamedFramebufferRenderbuffer)                         \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                                           \
    X(PFNGLTEXTUREBUFFERPROC, TextureBuffer)                                                       \
    X(PFNGLBINDTEXTUREUNITPROC, BindTextureUnit)                                                   \
    X(PFNGLVERTEXARRAYATTRIBIFORMATPROC, VertexArrayAttribIFormat)                                 \
    X(PFNGLPROGRAMUNIFORM1IPROC, ProgramUniform1i)                                                 \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                                                               \
    X(PFNGLDEPTHMASKPROC, DepthMask)                                                               \
    X(PFNGLPOLYGONMODEPROC, PolygonMode)                                                           \
    X(PfnPolygonOffset, PolygonOffset)                                                              \
    X(PFNGLLINEWIDTHPROC, LineWidth)                                                               \
    X(PFNGLPOINTSIZEPROC, PointSize)                                                               \
    X(PFNGLREADPIXELSPROC, ReadPixels)                                                             \
    X(PFNGLNAMEDBUFFERSUBDATAPROC, NamedBufferSubData)                                             \
    X(PfnDrawElements, DrawElements)                                                                \
    X(PFNGLVERTEXARRAYELEMENTBUFFERPROC, VertexArrayElementBuffer)                                 \
    X(PFNGLPROGRAMUNIFORM2FPROC, ProgramUniform2f)                                                 \
    X(PFNGLBLITNAMEDFRAMEBUFFERPROC, BlitNamedFramebuffer)                                         \
    X(PFNGLDRAWARRAYSINSTANCEDPROC, DrawArraysInstanced)                                           \
    X(PFNGLDRAWELEMENTSINSTANCEDPROC, DrawElementsInstanced)                                       \
    X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                                                     \
    X(PFNGLGETNAMEDBUFFERSUBDATAPROC, GetNamedBufferSubData)                                       \
    X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)                                                       \
    X(PFNGLDISPATCHCOMPUTEPROC, DispatchCompute)                                                   \
    X(PFNGLTEXTURESUBIMAGE2DPROC, TextureSubImage2D)                                               \
    X(PFNGLTEXTUREPARAMETERIPROC, TextureParameteri)                                               \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation)

using GetProcAddress = void* (*)(const char* name);

struct Functions {
#define SIGHTLINE_GL_DECLARE(type, name) type name = nullptr;
    SIGHTLINE_GL_FUNCTIONS(SIGHTLINE_GL_DECLARE)
#undef SIGHTLINE_GL_DECLARE

    /// Resolves every entry with `resolve` ("gl" + name). Throws sightline::Error naming the first
    /// missing function, or if the current context is older than OpenGL 4.5.
    void load(GetProcAddress resolve);
};

} // namespace sightline::gl
