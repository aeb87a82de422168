#pragma once
// GL programs for the samplers and the editor's viewport: shader compilation and linking with one-line errors.

#include <initializer_list>
#include <string>
#include <utility>

#include "visibility/gl/GlFunctions.h"

namespace sightline::gl {

/// Compiles and links one program from (stage, source) pairs. Throws sightline::Error, prefixed
/// with `what` (e.g. "GL bitmask sampler"), with the driver's log on one line.
GLuint buildProgram(const Functions& gl, std::initializer_list<std::pair<GLenum, std::string>> stages, const std::string& what);

} // namespace sightline::gl
