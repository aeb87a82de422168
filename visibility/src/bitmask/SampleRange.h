#pragma once
// Internal to the CPU bitmask sampler: which samples of a regular grid lie in an interval, and
// setting their bits. The one definition of this rounding in C++; the AVX2 kernel
// (BitmaskRowsAvx2.cpp) and the GL sampler's shader (GlShaders.h, kSampleRangeGlsl) have their
// own, in their languages, and tst_SampleRange checks the three against each other.

#include <algorithm>
#include <cstdint>

namespace sightline::bitmask {

/// Indices [first, last] of the samples at (k + 0.5) / n, k in [0, n), inside [lo, hi]; empty
/// when first > last. A sample exactly on the boundary counts as inside.
inline void sampleRange(double lo, double hi, int n, int& first, int& last)
{
    // floor/ceil by truncation: std::floor is a library call on baseline x86-64 and this runs
    // several times per (triangle, receiver sample) pair. Clamping first keeps the int in range
    // (and makes infinities, an edge that crossed nothing, harmless).
    const double x0 = std::clamp(lo * n - 0.5, -2.0, double(n) + 1.0);
    const double x1 = std::clamp(hi * n - 0.5, -2.0, double(n) + 1.0);
    const int c = int(x0);
    const int f = int(x1);
    first = std::max(0, c + (double(c) < x0));    // ceil
    last = std::min(n - 1, f - (double(f) > x1));  // floor
}

/// Indices [first, last] of the cells [k / n, (k + 1) / n] that meet [lo, hi]: where jittered
/// samples, anywhere in their cell, may lie.
inline void cellRange(double lo, double hi, int n, int& first, int& last)
{
    const double x0 = std::clamp(lo * n - 1.0, -2.0, double(n) + 1.0);
    const double x1 = std::clamp(hi * n, -2.0, double(n) + 1.0);
    const int c = int(x0);
    const int f = int(x1);
    first = std::max(0, c + (double(c) < x0));
    last = std::min(n - 1, f - (double(f) > x1));
}

/// Sets bits first..last (inclusive) of a row of 64-bit words.
inline void setBitRange(std::uint64_t* words, int first, int last)
{
    const int w0 = first >> 6, w1 = last >> 6;
    const std::uint64_t lowMask = ~std::uint64_t(0) << (first & 63);
    const std::uint64_t highMask = ~std::uint64_t(0) >> (63 - (last & 63));
    if (w0 == w1) {
        words[w0] |= lowMask & highMask;
        return;
    }
    words[w0] |= lowMask;
    for (int w = w0 + 1; w < w1; ++w)
        words[w] = ~std::uint64_t(0);
    words[w1] |= highMask;
}

/// Whether all `sources` bits of a row are set.
inline bool rowFull(const std::uint64_t* row, int words, int sources)
{
    for (int w = 0; w + 1 < words; ++w)
        if (row[w] != ~std::uint64_t(0))
            return false;
    const int rest = sources - 64 * (words - 1);
    const std::uint64_t last = rest == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << rest) - 1;
    return row[words - 1] == last;
}

} // namespace sightline::bitmask
