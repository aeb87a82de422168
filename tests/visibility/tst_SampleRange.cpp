// The sample-range rounding has one definition per language (bitmask/SampleRange.h in C++, the
// AVX2 kernel's in BitmaskRowsAvx2.cpp, kSampleRangeGlsl in the GL samplers; the GLSL one is
// checked in tst_GlSampleRange): the same answers, except where float rounding of lo * n - 0.5
// lands within an ulp of an integer, which the kernels' error bounds cover.

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "BitmaskRows.h"
#include "bitmask/SampleRange.h"

using namespace sightline;

namespace {

/// Whether x * n - 0.5 (x float) lies within two float ulps of x * n from an integer: where a float
/// evaluation may round to the other side.
bool nearSampleBoundary(float x, int n)
{
    const double y = double(x) * n - 0.5;   // exact: 24 + 11 bits
    const double ulp = (std::abs(double(x) * n) + 0.5) * std::numeric_limits<float>::epsilon();   // of the product, rounded before the 0.5 is taken (unless fused)
    return std::abs(y - std::round(y)) <= 2.0 * ulp;
}

} // namespace

TEST(SampleRange, CountsBoundarySamplesInsideAndClampsToTheGrid)
{
    int first, last;
    bitmask::sampleRange(0.25, 0.75, 4, first, last);   // samples at 0.125, 0.375, 0.625, 0.875
    EXPECT_EQ(first, 1);
    EXPECT_EQ(last, 2);
    bitmask::sampleRange(0.375, 0.375, 4, first, last);   // exactly on sample 1: inside
    EXPECT_EQ(first, 1);
    EXPECT_EQ(last, 1);
    bitmask::sampleRange(-1e30, 1e30, 4, first, last);
    EXPECT_EQ(first, 0);
    EXPECT_EQ(last, 3);
    bitmask::sampleRange(0.4, 0.6, 4, first, last);   // between samples: empty
    EXPECT_GT(first, last);
    bitmask::sampleRange(std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), 4, first, last);
    EXPECT_GT(first, last);
    // Cells (jittered samples lie anywhere in theirs): [0.4, 0.6] meets cells 1 and 2.
    bitmask::cellRange(0.4, 0.6, 4, first, last);
    EXPECT_EQ(first, 1);
    EXPECT_EQ(last, 2);
    bitmask::cellRange(0.5, 0.5, 4, first, last);   // on the edge between cells 1 and 2: both
    EXPECT_EQ(first, 1);
    EXPECT_EQ(last, 2);
}

TEST(SampleRange, TheKernelRoundsAsTheDoubleDefinitionDoes)
{
    if (!detail::floatRowsAvailable())
        GTEST_SKIP() << "no AVX2 on this CPU";
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> unit(-0.25f, 1.25f);
    int compared = 0, boundary = 0;
    for (int n : {1, 3, 7, 32, 1000}) {
        for (int round = 0; round < 4000; ++round) {
            float lo[8], hi[8];
            int first[8], last[8];
            for (int l = 0; l < 8; ++l) {
                lo[l] = unit(rng), hi[l] = lo[l] + 0.3f * unit(rng);
                // Some exactly on sample positions (exact in float for these n up to rounding).
                if (l == 7)
                    lo[l] = (float(rng() % std::uint32_t(n)) + 0.5f) / float(n);
            }
            detail::sampleRangeFloat8(lo, hi, n, first, last);
            for (int l = 0; l < 8; ++l) {
                int f, t;
                bitmask::sampleRange(lo[l], hi[l], n, f, t);
                if (nearSampleBoundary(lo[l], n) || nearSampleBoundary(hi[l], n)) {
                    ++boundary;
                    EXPECT_LE(std::abs(first[l] - f), 1);
                    EXPECT_LE(std::abs(last[l] - t), 1);
                    continue;
                }
                ++compared;
                if (f <= t) {
                    ASSERT_EQ(first[l], f) << lo[l] << " " << hi[l] << " n " << n;
                    ASSERT_EQ(last[l], t) << lo[l] << " " << hi[l] << " n " << n;
                } else {
                    ASSERT_GT(first[l], last[l]) << lo[l] << " " << hi[l] << " n " << n;
                }
            }
        }
    }
    EXPECT_GT(compared, 100000);
    EXPECT_GT(boundary, 1000);   // the exact sample positions were tried
}

TEST(SampleRange, TheKernelClampsHugeAndInfiniteEnds)
{
    if (!detail::floatRowsAvailable())
        GTEST_SKIP() << "no AVX2 on this CPU";
    const float inf = std::numeric_limits<float>::infinity();
    float lo[8] = {-inf, -1e30f, 0.5f, inf, -inf, 2.0f, -3.0f, 0.0f};
    float hi[8] = {inf, 1e30f, inf, inf, -inf, 3.0f, -2.0f, 1.0f};
    int first[8], last[8];
    detail::sampleRangeFloat8(lo, hi, 32, first, last);
    for (int l = 0; l < 8; ++l) {
        int f, t;
        bitmask::sampleRange(lo[l], hi[l], 32, f, t);
        EXPECT_EQ(first[l] <= last[l], f <= t) << l;
        if (f <= t) {
            EXPECT_EQ(first[l], f) << l;
            EXPECT_EQ(last[l], t) << l;
        }
    }
}
