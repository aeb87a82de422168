#include "visibility/gl/GlFunctions.h"

#include <cstdio>

#include "base/Error.h"

namespace sightline::gl {

void Functions::load(GetProcAddress resolve)
{
#define SIGHTLINE_GL_RESOLVE(type, name)                                                            \
    name = reinterpret_cast<type>(resolve("gl" #name));                                             \
    if (!name)                                                                                      \
        throw Error("OpenGL: the current context has no gl" #name " (OpenGL 4.5 core is required)");
    SIGHTLINE_GL_FUNCTIONS(SIGHTLINE_GL_RESOLVE)
#undef SIGHTLINE_GL_RESOLVE
    GLint major = 0, minor = 0;
    GetIntegerv(GL_MAJOR_VERSION, &major);
    GetIntegerv(GL_MINOR_VERSION, &minor);
    if (major < 4 || (major == 4 && minor < 5))
        throw Error("OpenGL 4.5 core is required; the current context is " + std::to_string(major) + "." +
                    std::to_string(minor));
}

} // namespace sightline::gl
