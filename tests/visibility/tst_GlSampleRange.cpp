// The GLSL definition of the sample-range rounding (kSampleRangeGlsl) against the C++ one
// (bitmask/SampleRange.h), run in a compute shader: the same answers, except within two float
// ulps of a sample boundary (tst_SampleRange does the same for the AVX2 kernel).

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "GlContextTest.h"
#include "bitmask/SampleRange.h"
#include "visibility/gl/GlShaders.h"

using namespace sightline;
using namespace sightline::test;

namespace {

class GlSampleRange : public GlContextTest {};

bool nearSampleBoundary(float x, int n)
{
    const double y = double(x) * n - 0.5;
    const double ulp = (std::abs(double(x) * n) + 0.5) * std::numeric_limits<float>::epsilon();   // of the product, rounded before the 0.5 is taken (unless fused)
    return std::abs(y - std::round(y)) <= 2.0 * ulp;
}

} // namespace

TEST_F(GlSampleRange, TheShaderRoundsAsTheDoubleDefinitionDoes)
{
    const gl::Functions& gl = context->functions();
    const std::string source = std::string("#version 450 core\nlayout(local_size_x = 64) in;\n") + gl::kSampleRangeGlsl + R"(
layout(std430, binding = 0) readonly buffer Inputs { vec2 intervals[]; };
layout(std430, binding = 1) writeonly buffer Outputs { ivec2 ranges[]; };
uniform int uN;
void main() { uint i = gl_GlobalInvocationID.x; ranges[i] = sampleRange(intervals[i].x, intervals[i].y, uN); }
)";
    const GLuint program = gl::buildProgram(gl, {{GL_COMPUTE_SHADER, source}}, "sample range test");
    constexpr int kCount = 64 * 256;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(-0.25f, 1.25f);
    GLuint buffers[2];
    gl.CreateBuffers(2, buffers);
    int compared = 0;
    for (int n : {1, 3, 32, 1000}) {
        std::vector<float> intervals(2 * kCount);
        for (int i = 0; i < kCount; ++i) {
            intervals[2 * i] = i % 8 == 7 ? (float(rng() % std::uint32_t(n)) + 0.5f) / float(n) : unit(rng);
            intervals[2 * i + 1] = intervals[2 * i] + 0.3f * unit(rng);
        }
        gl.NamedBufferData(buffers[0], GLsizeiptr(intervals.size() * sizeof(float)), intervals.data(), GL_STATIC_DRAW);
        gl.NamedBufferData(buffers[1], GLsizeiptr(2 * kCount * sizeof(int)), nullptr, GL_STATIC_READ);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[0]);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers[1]);
        gl.UseProgram(program);
        gl.ProgramUniform1i(program, gl.GetUniformLocation(program, "uN"), n);
        gl.DispatchCompute(kCount / 64, 1, 1);
        gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<int> ranges(2 * kCount);
        gl.GetNamedBufferSubData(buffers[1], 0, GLsizeiptr(ranges.size() * sizeof(int)), ranges.data());
        for (int i = 0; i < kCount; ++i) {
            const float lo = intervals[2 * i], hi = intervals[2 * i + 1];
            int f, t;
            bitmask::sampleRange(lo, hi, n, f, t);
            if (nearSampleBoundary(lo, n) || nearSampleBoundary(hi, n)) {
                EXPECT_LE(std::abs(ranges[2 * i] - f), 1);
                continue;
            }
            ++compared;
            if (f <= t) {
                ASSERT_EQ(ranges[2 * i], f) << lo << " " << hi << " n " << n;
                ASSERT_EQ(ranges[2 * i + 1], t) << lo << " " << hi << " n " << n;
            } else {
                ASSERT_GT(ranges[2 * i], ranges[2 * i + 1]) << lo << " " << hi << " n " << n;
            }
        }
    }
    gl.DeleteBuffers(2, buffers);
    gl.DeleteProgram(program);
    EXPECT_GT(compared, 50000);
}
