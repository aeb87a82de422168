#pragma once
// GL programs for the samplers and the editor's viewport: shader compilation and linking with one-line errors,
// and the vertex array every positions-only pass shares.

#include <initializer_list>
#include <string>
#include <utility>

#include "visibility/gl/GlFunctions.h"

namespace sightline::gl {

/// GLSL: `ivec2 sampleRange(float lo, float hi, int n)`, the indices (first, last) of the samples
/// at (k + 0.5) / n inside [lo, hi], empty when first > last: the rounding of the CPU sampler's
/// SampleRange.h, in the samplers' shaders (tst_SampleRange checks the languages against each
/// other).
extern const char* const kSampleRangeGlsl;

/// Compiles and links one program from (stage, source) pairs. Throws sightline::Error, prefixed
/// with `what` (e.g. "GL bitmask sampler"), with the driver's log on one line.
GLuint buildProgram(const Functions& gl, std::initializer_list<std::pair<GLenum, std::string>> stages, const std::string& what);

/// A vertex array reading tightly packed vec3 positions from `buffer` as attribute 0 (the depth
/// and shadow-map passes draw positions alone).
GLuint positionVertexArray(const Functions& gl, GLuint buffer);

} // namespace sightline::gl
