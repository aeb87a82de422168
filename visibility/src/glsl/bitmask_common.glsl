// GlBitmaskSampler.cpp: what both fragment shaders share (after "#version", the TARGETS define,
// the outputs and GlShaders.h's sampleRange): the occluders, the samples, the mask.
struct Polygon {
    ivec4 info;
    vec4 hi[8];
    vec4 lo[8];
};
layout(std430, binding = 0) readonly buffer Polygons { Polygon polygons[]; };
// Per receiver sample: (s, t, d) in the source frame, their residuals, the jitter shift (§6.2).
layout(std430, binding = 1) readonly buffer Samples { vec4 samples[]; };
flat in int vPolygon;
uniform ivec2 uSourceGrid, uReceiverGrid;

uint mask[4 * TARGETS];

void setRange(int first, int last)
{
    for (int w = first >> 5; w <= (last >> 5); ++w) {
        int a = max(first, w * 32) - w * 32, b = min(last, w * 32 + 31) - w * 32;
        uint bits = (b == 31 ? 0xffffffffu : ((1u << (b + 1)) - 1u)) & ~((1u << a) - 1u);
        mask[w] |= bits;
    }
}
