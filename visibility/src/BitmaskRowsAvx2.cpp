#include "BitmaskRows.h"

#include <algorithm>
#include <bit>
#include <limits>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define SIGHTLINE_X86 1
#endif

namespace sightline::detail {

#ifdef SIGHTLINE_X86

bool floatRowsAvailable()
{
    static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return available;
}

namespace {

#define SIGHTLINE_AVX2 __attribute__((target("avx2,fma")))

/// Indices of the samples at (k + 0.5) / n inside [lo, hi]: ceil(lo n - 0.5) and floor(hi n - 0.5),
/// clamped to the grid (same rule as the scalar path's sampleRange). Clamping before converting
/// keeps infinities (no edge crossed the row) and huge values in int range.
SIGHTLINE_AVX2 inline void sampleRange(__m256 lo, __m256 hi, int n, __m256i& first, __m256i& last)
{
    const __m256 nf = _mm256_set1_ps(float(n)), half = _mm256_set1_ps(0.5f);
    const __m256 floor = _mm256_set1_ps(-2.0f), ceiling = _mm256_set1_ps(float(n) + 1.0f);
    const __m256 x0 = _mm256_min_ps(_mm256_max_ps(_mm256_fmsub_ps(lo, nf, half), floor), ceiling);
    const __m256 x1 = _mm256_min_ps(_mm256_max_ps(_mm256_fmsub_ps(hi, nf, half), floor), ceiling);
    first = _mm256_max_epi32(_mm256_cvtps_epi32(_mm256_round_ps(x0, _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC)),
                             _mm256_setzero_si256());
    last = _mm256_min_epi32(_mm256_cvtps_epi32(_mm256_round_ps(x1, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)),
                            _mm256_set1_epi32(n - 1));
}

/// Widens [lo, hi] by `slack`. Two triangles sharing an edge compute that edge from different
/// vertices, so in single precision a sample exactly on it (a wall of two triangles with the
/// patches centred on its diagonal puts hundreds of rays there) could fall outside both: a crack
/// the reference (watertight Embree) does not have. The slack covers the rounding of the
/// backprojected coordinates and errs towards blocked on rays within it of an edge only.
SIGHTLINE_AVX2 inline void widen(__m256& lo, __m256& hi, __m256 slack)
{
    lo = _mm256_sub_ps(lo, slack);
    hi = _mm256_add_ps(hi, slack);
}

} // namespace

SIGHTLINE_AVX2 int backprojectRowsAvx2(const FloatPolygon& polygon, const LaneGroup& lanes, int na, int nb)
{
    unsigned activeLanes = 0;
    for (int l = 0; l < kLanes; ++l)
        activeLanes |= unsigned(lanes.rows[l] != nullptr) << l;
    if (!activeLanes)
        return 0;
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    const __m256 negInf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());

    // Backprojection of every vertex from every lane's receiver sample (ShaftGeometry.h).
    const __m256 rs = _mm256_load_ps(lanes.s), rt = _mm256_load_ps(lanes.t), rd = _mm256_load_ps(lanes.d);
    const __m256 shiftS = _mm256_load_ps(lanes.shiftS), shiftT = _mm256_load_ps(lanes.shiftT);
    __m256 ps[kMaxPolygon], pt[kMaxPolygon];
    __m256 tMin = inf, tMax = negInf, magnitude = _mm256_setzero_ps();
    const __m256 sign = _mm256_set1_ps(-0.0f);
    for (int i = 0; i < polygon.count; ++i) {
        const __m256 k = _mm256_div_ps(rd, _mm256_sub_ps(rd, _mm256_set1_ps(polygon.d[i])));
        ps[i] = _mm256_sub_ps(_mm256_fmadd_ps(_mm256_sub_ps(_mm256_set1_ps(polygon.s[i]), rs), k, rs), shiftS);
        pt[i] = _mm256_sub_ps(_mm256_fmadd_ps(_mm256_sub_ps(_mm256_set1_ps(polygon.t[i]), rt), k, rt), shiftT);
        tMin = _mm256_min_ps(tMin, pt[i]);
        tMax = _mm256_max_ps(tMax, pt[i]);
        magnitude = _mm256_max_ps(magnitude, _mm256_max_ps(_mm256_andnot_ps(sign, ps[i]), _mm256_andnot_ps(sign, pt[i])));
    }
    // Rounding of an edge's crossing is relative to the coordinates it is computed from (the
    // vertices), not to its result: 2^-20 of the largest, a few ulps after the projection (factor
    // <= kMaxFloatFactor) and the interpolation, plus 2^-24 of the patch.
    const __m256 slack = _mm256_fmadd_ps(magnitude, _mm256_set1_ps(1.0f / 1048576.0f), _mm256_set1_ps(1.0f / 16777216.0f));
    __m256i b0, b1;
    widen(tMin, tMax, slack);
    sampleRange(tMin, tMax, nb, b0, b1);
    alignas(32) int first[kLanes], last[kLanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(first), b0);
    _mm256_store_si256(reinterpret_cast<__m256i*>(last), b1);
    int rowMin = nb, rowMax = -1;
    for (unsigned m = activeLanes; m; m &= m - 1) {
        const int l = std::countr_zero(m);
        rowMin = std::min(rowMin, first[l]);
        rowMax = std::max(rowMax, last[l]);
    }
    // Inactive lanes get an empty row range, so they never write.
    alignas(32) int laneOn[kLanes];
    for (int l = 0; l < kLanes; ++l)
        laneOn[l] = (activeLanes >> l & 1) ? -1 : 0;
    const __m256i on = _mm256_load_si256(reinterpret_cast<const __m256i*>(laneOn));
    b0 = _mm256_blendv_epi8(_mm256_set1_epi32(nb), b0, on);

    // Edges: per row t = tb, an edge spanning tb crosses at lo + (tb - t0) * slope. An edge along
    // the row (t0 == t1) contributes both ends: slope 0, lo and hi its extremes.
    const int count = polygon.count;
    __m256 eLo[kMaxPolygon], eHi[kMaxPolygon], eT[kMaxPolygon], eSlope[kMaxPolygon], eMin[kMaxPolygon],
        eMax[kMaxPolygon];
    for (int i = 0, k = count - 1; i < count; k = i++) {
        const __m256 flat = _mm256_cmp_ps(pt[k], pt[i], _CMP_EQ_OQ);
        const __m256 slope = _mm256_div_ps(_mm256_sub_ps(ps[i], ps[k]), _mm256_sub_ps(pt[i], pt[k]));
        eSlope[i] = _mm256_blendv_ps(slope, _mm256_setzero_ps(), flat);
        eLo[i] = _mm256_blendv_ps(ps[k], _mm256_min_ps(ps[k], ps[i]), flat);
        eHi[i] = _mm256_blendv_ps(ps[k], _mm256_max_ps(ps[k], ps[i]), flat);
        eT[i] = pt[k];
        eMin[i] = _mm256_min_ps(pt[k], pt[i]);
        eMax[i] = _mm256_max_ps(pt[k], pt[i]);
        widen(eMin[i], eMax[i], slack);
    }

    const __m256i one = _mm256_set1_epi32(1), two = _mm256_set1_epi32(2);
    alignas(32) std::uint32_t bits[kLanes];
    for (int b = rowMin; b <= rowMax; ++b) {
        const __m256 tb = _mm256_set1_ps((float(b) + 0.5f) / float(nb));
        __m256 lo = inf, hi = negInf;
        for (int e = 0; e < count; ++e) {
            const __m256 spans = _mm256_and_ps(_mm256_cmp_ps(tb, eMin[e], _CMP_GE_OQ), _mm256_cmp_ps(tb, eMax[e], _CMP_LE_OQ));
            const __m256 dt = _mm256_sub_ps(tb, eT[e]);
            // min/max return their second operand when the first is NaN: the accumulator survives.
            lo = _mm256_min_ps(_mm256_blendv_ps(inf, _mm256_fmadd_ps(dt, eSlope[e], eLo[e]), spans), lo);
            hi = _mm256_max_ps(_mm256_blendv_ps(negInf, _mm256_fmadd_ps(dt, eSlope[e], eHi[e]), spans), hi);
        }
        __m256i a0, a1;
        widen(lo, hi, slack);
        sampleRange(lo, hi, na, a0, a1);
        const __m256i row = _mm256_set1_epi32(b);
        const __m256i outside = _mm256_or_si256(
            _mm256_or_si256(_mm256_cmpgt_epi32(b0, row), _mm256_cmpgt_epi32(row, b1)), _mm256_cmpgt_epi32(a0, a1));
        // Bits a0..a1: (2 << a1) - (1 << a0); for a1 = 31 the first term wraps to 0, still right.
        const __m256i run = _mm256_sub_epi32(_mm256_sllv_epi32(two, a1), _mm256_sllv_epi32(one, a0));
        const __m256i masked = _mm256_andnot_si256(outside, run);
        const unsigned empty = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(masked, _mm256_setzero_si256()))));
        unsigned written = ~empty & 0xffu;
        if (!written)
            continue;
        _mm256_store_si256(reinterpret_cast<__m256i*>(bits), masked);
        const int position = b * na, word = position >> 6, shift = position & 63;
        for (; written; written &= written - 1) {
            const int l = std::countr_zero(written);
            std::uint64_t* out = lanes.rows[l];
            out[word] |= std::uint64_t(bits[l]) << shift;
            if (shift + na > 64)
                out[word + 1] |= std::uint64_t(bits[l]) >> (64 - shift);
        }
    }
    return std::popcount(activeLanes);
}

#else

bool floatRowsAvailable() { return false; }
int backprojectRowsAvx2(const FloatPolygon&, const LaneGroup&, int, int) { return 0; }

#endif

} // namespace sightline::detail
