#include "visibility/gl/GlShaders.h"

#include <algorithm>
#include <vector>

#include "base/Error.h"

namespace sightline::gl {

const char* const kSampleRangeGlsl = R"(
ivec2 sampleRange(float lo, float hi, int n)
{
    float x0 = clamp(lo * float(n) - 0.5, -2.0, float(n) + 1.0);
    float x1 = clamp(hi * float(n) - 0.5, -2.0, float(n) + 1.0);
    return ivec2(max(0, int(ceil(x0))), min(n - 1, int(floor(x1))));
}
)";

namespace {

std::string oneLine(std::string log)
{
    std::replace(log.begin(), log.end(), '\n', ' ');
    while (!log.empty() && log.back() == ' ')
        log.pop_back();
    return log.substr(0, 400);
}

const char* stageName(GLenum stage)
{
    switch (stage) {
    case GL_VERTEX_SHADER: return "vertex";
    case GL_GEOMETRY_SHADER: return "geometry";
    case GL_FRAGMENT_SHADER: return "fragment";
    default: return "compute";
    }
}

} // namespace

GLuint buildProgram(const Functions& gl, std::initializer_list<std::pair<GLenum, std::string>> stages, const std::string& what)
{
    std::vector<GLuint> shaders;
    auto deleteShaders = [&] {
        for (GLuint s : shaders)
            gl.DeleteShader(s);
    };
    for (const auto& [stage, source] : stages) {
        const GLuint shader = gl.CreateShader(stage);
        shaders.push_back(shader);
        const char* text = source.c_str();
        gl.ShaderSource(shader, 1, &text, nullptr);
        gl.CompileShader(shader);
        GLint ok = 0;
        gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            char log[4096] = {};
            gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
            deleteShaders();
            throw Error(what + ": " + stageName(stage) + " shader does not compile: " + oneLine(log));
        }
    }
    const GLuint program = gl.CreateProgram();
    for (GLuint s : shaders)
        gl.AttachShader(program, s);
    gl.LinkProgram(program);
    deleteShaders();
    GLint ok = 0;
    gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        gl.GetProgramInfoLog(program, sizeof log, nullptr, log);
        gl.DeleteProgram(program);
        throw Error(what + ": program does not link: " + oneLine(log));
    }
    return program;
}

GLuint positionVertexArray(const Functions& gl, GLuint buffer)
{
    GLuint vao = 0;
    gl.CreateVertexArrays(1, &vao);
    gl.VertexArrayVertexBuffer(vao, 0, buffer, 0, 3 * sizeof(float));
    gl.VertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl.VertexArrayAttribBinding(vao, 0, 0);
    gl.EnableVertexArrayAttrib(vao, 0);
    return vao;
}

} // namespace sightline::gl
