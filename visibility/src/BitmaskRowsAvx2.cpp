#include "BitmaskRows.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define SIGHTLINE_X86 1
#endif

namespace sightline::detail {

#ifdef SIGHTLINE_X86

// SSE2, baseline on x86-64: the four corners side by side.
void backprojectedBounds(const FloatPolygon& polygon, const float rs[4], const float rt[4], const float rd[4],
                         float out[4])
{
    const __m128 s0 = _mm_loadu_ps(rs), t0 = _mm_loadu_ps(rt), d0 = _mm_loadu_ps(rd);
    __m128 sMin = _mm_set1_ps(std::numeric_limits<float>::infinity()), tMin = sMin;
    __m128 sMax = _mm_set1_ps(-std::numeric_limits<float>::infinity()), tMax = sMax;
    for (int i = 0; i < polygon.count; ++i) {
        const __m128 k = polygon.sharedFactor ? _mm_set1_ps(polygon.k[i])
                                              : _mm_div_ps(d0, _mm_sub_ps(d0, _mm_set1_ps(polygon.d[i])));
        const __m128 s = _mm_add_ps(s0, _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(polygon.s[i]), s0), k));
        const __m128 t = _mm_add_ps(t0, _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(polygon.t[i]), t0), k));
        sMin = _mm_min_ps(sMin, s), sMax = _mm_max_ps(sMax, s);
        tMin = _mm_min_ps(tMin, t), tMax = _mm_max_ps(tMax, t);
    }
    // Horizontal: [sMin, tMin] and [sMax, tMax] pairs reduced together.
    __m128 lo = _mm_min_ps(_mm_unpacklo_ps(sMin, tMin), _mm_unpackhi_ps(sMin, tMin));   // s01 t01 s23 t23
    __m128 hi = _mm_max_ps(_mm_unpacklo_ps(sMax, tMax), _mm_unpackhi_ps(sMax, tMax));
    lo = _mm_min_ps(lo, _mm_movehl_ps(lo, lo));   // s, t in lanes 0, 1
    hi = _mm_max_ps(hi, _mm_movehl_ps(hi, hi));
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    out[0] = l[0], out[1] = h[0], out[2] = l[1], out[3] = h[1];
}

#else

void backprojectedBounds(const FloatPolygon& polygon, const float rs[4], const float rt[4], const float rd[4],
                         float out[4])
{
    out[0] = out[2] = std::numeric_limits<float>::infinity();
    out[1] = out[3] = -std::numeric_limits<float>::infinity();
    for (int i = 0; i < polygon.count; ++i)
        for (int c = 0; c < 4; ++c) {
            const float k = polygon.sharedFactor ? polygon.k[i] : rd[c] / (rd[c] - polygon.d[i]);
            const float s = rs[c] + (polygon.s[i] - rs[c]) * k, t = rt[c] + (polygon.t[i] - rt[c]) * k;
            out[0] = std::min(out[0], s), out[1] = std::max(out[1], s);
            out[2] = std::min(out[2], t), out[3] = std::max(out[3], t);
        }
}

#endif

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

SIGHTLINE_AVX2 inline int horizontalMin(__m256i v)
{
    __m128i m = _mm_min_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    m = _mm_min_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtsi128_si32(_mm_min_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1))));
}

SIGHTLINE_AVX2 inline int horizontalMax(__m256i v)
{
    __m128i m = _mm_max_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    m = _mm_max_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtsi128_si32(_mm_max_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1))));
}

/// Widens [lo, hi] by `slack`.
SIGHTLINE_AVX2 inline void widen(__m256& lo, __m256& hi, __m256 slack)
{
    lo = _mm256_sub_ps(lo, slack);
    hi = _mm256_add_ps(hi, slack);
}

SIGHTLINE_AVX2 inline __m256 absolute(__m256 x) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), x); }

/// The source-plane error of a lane's backprojection, at most k times its ray term per vertex
/// (needed to widen a closed mesh, and to tell lanes over the budget that have nothing to
/// answer), as slacks in source units; and the smallest factor.
[[gnu::always_inline]] SIGHTLINE_AVX2 inline void sourcePlaneError(int count, const __m256* rayS, const __m256* rayT,
                                                                   const __m256* factor, __m256 unit, __m256& slackS,
                                                                   __m256& slackT, __m256& kMin)
{
    __m256 eS = _mm256_setzero_ps(), eT = eS;
    kMin = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    for (int i = 0; i < count; ++i) {
        eS = _mm256_max_ps(eS, _mm256_mul_ps(rayS[i], factor[i]));
        eT = _mm256_max_ps(eT, _mm256_mul_ps(rayT[i], factor[i]));
        kMin = _mm256_min_ps(kMin, factor[i]);
    }
    const __m256 two = _mm256_set1_ps(2.0f);
    slackS = _mm256_mul_ps(unit, _mm256_add_ps(eS, two));
    slackT = _mm256_mul_ps(unit, _mm256_add_ps(eT, two));
}

/// One vector of the eight lanes per polygon vertex, or per edge (edge i ends at vertex i).
using PerVertex = __m256[kMaxPolygon];

/// Backprojection of every vertex from every lane's receiver sample, with the ray terms of the
/// per-lane error bound (not for `Proven`); accumulates t's range and the largest ray terms.
template <bool Proven>
[[gnu::always_inline]] SIGHTLINE_AVX2 inline void
backprojectVertices(const FloatPolygon& polygon, const LaneGroup& lanes, PerVertex& ps, PerVertex& pt,
                    PerVertex& magnitude, PerVertex& factor, PerVertex& rayS, PerVertex& rayT, __m256& tMin,
                    __m256& tMax, __m256& rayMaxS, __m256& rayMaxT)
{
    // Backprojection of every vertex from every lane's receiver sample (ShaftGeometry.h):
    // p = r + (x - r) k with k = d_r / (d_r - d_x). Inputs come as float pairs (value and its
    // rounding residual), so the differences x - r and d_r - d_x are accurate to a few ulps of
    // themselves, not of the coordinates: otherwise the projection multiplies the coordinates'
    // rounding by up to 2k + 3. Per lane, a bound on how far the float answer can stray from the
    // double one, as a distance between ray and occluder boundary (the header's filter): per
    // vertex and axis, in source units and float epsilons,
    //   6 |x - r| + (|r| + 4 |p|) / k
    // (the difference and the factor; then r's residual, the result, the crossings and the
    // comparisons, which the projection does not stretch in ray terms).
    const __m256 rs = _mm256_load_ps(lanes.s), rt = _mm256_load_ps(lanes.t), rd = _mm256_load_ps(lanes.d);
    const __m256 rsLo = _mm256_load_ps(lanes.sLo), rtLo = _mm256_load_ps(lanes.tLo), rdLo = _mm256_load_ps(lanes.dLo);
    const __m256 shiftS = _mm256_load_ps(lanes.shiftS), shiftT = _mm256_load_ps(lanes.shiftT);
    const __m256 rsAbs = absolute(rs), rtAbs = absolute(rt);
    const __m256 six = _mm256_set1_ps(6.0f), four = _mm256_set1_ps(4.0f);
    for (int i = 0; i < polygon.count; ++i) {
        const __m256 k =
            polygon.sharedFactor
                ? _mm256_set1_ps(polygon.k[i])
                : _mm256_div_ps(rd, _mm256_add_ps(_mm256_sub_ps(rd, _mm256_set1_ps(polygon.d[i])),
                                                  _mm256_sub_ps(rdLo, _mm256_set1_ps(polygon.dLo[i]))));
        __m256 dS = _mm256_sub_ps(_mm256_set1_ps(polygon.s[i]), rs);
        __m256 dT = _mm256_sub_ps(_mm256_set1_ps(polygon.t[i]), rt);
        if constexpr (!Proven) {
            dS = _mm256_add_ps(dS, _mm256_sub_ps(_mm256_set1_ps(polygon.sLo[i]), rsLo));
            dT = _mm256_add_ps(dT, _mm256_sub_ps(_mm256_set1_ps(polygon.tLo[i]), rtLo));
        }
        ps[i] = _mm256_fmadd_ps(dS, k, rs);
        pt[i] = _mm256_fmadd_ps(dT, k, rt);
        if (lanes.shifted) {
            ps[i] = _mm256_sub_ps(ps[i], shiftS);
            pt[i] = _mm256_sub_ps(pt[i], shiftT);
        }
        tMin = _mm256_min_ps(tMin, pt[i]);
        tMax = _mm256_max_ps(tMax, pt[i]);
        const __m256 psAbs = absolute(ps[i]), ptAbs = absolute(pt[i]);
        magnitude[i] = _mm256_add_ps(psAbs, ptAbs);
        if constexpr (!Proven) {
            factor[i] = k;
            const __m256 kInverse = _mm256_rcp_ps(k);   // 1.5e-4 relative: the bound is scaled up for it
            rayS[i] = _mm256_fmadd_ps(six, absolute(dS), _mm256_mul_ps(_mm256_fmadd_ps(four, psAbs, rsAbs), kInverse));
            rayT[i] = _mm256_fmadd_ps(six, absolute(dT), _mm256_mul_ps(_mm256_fmadd_ps(four, ptAbs, rtAbs), kInverse));
            rayMaxS = _mm256_max_ps(rayMaxS, rayS[i]);
            rayMaxT = _mm256_max_ps(rayMaxT, rayT[i]);
        }
    }
}

/// Per lane, the band of possibly misclassified samples in metres (a closed mesh's widening by
/// its source-plane error included, which sets slackS, slackT and kMin).
[[gnu::always_inline]] SIGHTLINE_AVX2 inline __m256 errorBand(const FloatPolygon& polygon, const LaneGroup& lanes,
                                                             const PerVertex& rayS, const PerVertex& rayT,
                                                             const PerVertex& factor, __m256 rayMaxS, __m256 rayMaxT,
                                                             __m256 unit, __m256& slackS, __m256& slackT, __m256& kMin)
{
    const __m256 two = _mm256_set1_ps(2.0f);
    const __m256 metresS = _mm256_set1_ps(lanes.metresPerS), metresT = _mm256_set1_ps(lanes.metresPerT);
    __m256 band = _mm256_mul_ps(unit, _mm256_fmadd_ps(_mm256_add_ps(rayMaxS, two), metresS,
                                                      _mm256_mul_ps(_mm256_add_ps(rayMaxT, two), metresT)));
    if (polygon.closed) {
        // Widening a closed mesh's intervals by its source-plane error adds that error over
        // the smallest k to the band.
        sourcePlaneError(polygon.count, rayS, rayT, factor, unit, slackS, slackT, kMin);
        band = _mm256_add_ps(band, _mm256_div_ps(_mm256_fmadd_ps(slackS, metresS, _mm256_mul_ps(slackT, metresT)), kMin));
    }
    return band;
}

/// The lanes whose backprojection, widened by slackS and slackT, holds no sample of the grid.
[[gnu::always_inline]] SIGHTLINE_AVX2 inline unsigned holdingNoSample(int count, const PerVertex& ps, __m256 tMin,
                                                                     __m256 tMax, __m256 slackS, __m256 slackT,
                                                                     int na, int nb)
{
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    const __m256 negInf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
    __m256 sMin = inf, sMax = negInf;
    for (int i = 0; i < count; ++i)
        sMin = _mm256_min_ps(sMin, ps[i]), sMax = _mm256_max_ps(sMax, ps[i]);
    __m256i c0, c1, r0, r1;
    __m256 bottom = tMin, top = tMax;
    widen(sMin, sMax, slackS);
    widen(bottom, top, slackT);
    sampleRange(sMin, sMax, na, c0, c1);
    sampleRange(bottom, top, nb, r0, r1);
    const __m256i none = _mm256_or_si256(_mm256_cmpgt_epi32(c0, c1), _mm256_cmpgt_epi32(r0, r1));
    return unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(none)));
}

/// The rows of samples that t's range, widened by widenT, holds per lane ([b0, b1]; empty for
/// inactive lanes), and their union [rowMin, rowMax].
[[gnu::always_inline]] SIGHTLINE_AVX2 inline void rowRange(unsigned activeLanes, int nb, __m256 widenT, __m256 tMin,
                                                          __m256 tMax, __m256i& b0, __m256i& b1, int& rowMin,
                                                          int& rowMax)
{
    widen(tMin, tMax, widenT);
    sampleRange(tMin, tMax, nb, b0, b1);
    // Inactive lanes get an empty row range, so their bits stay zero.
    const __m256i laneBit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i on = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(activeLanes)), laneBit), laneBit);
    b0 = _mm256_blendv_epi8(_mm256_set1_epi32(nb), b0, on);
    rowMin = horizontalMin(b0), rowMax = horizontalMax(_mm256_blendv_epi8(_mm256_set1_epi32(-1), b1, on));
}

/// Per edge and lane, what a row's crossing needs: its start, slope, span of t (left out along
/// the row) and span of s.
[[gnu::always_inline]] SIGHTLINE_AVX2 inline void
edgeCrossings(int count, const PerVertex& ps, const PerVertex& pt, const PerVertex& magnitude, __m256 widenT,
              PerVertex& eBase, PerVertex& eT0, PerVertex& eSlope, PerVertex& eMin, PerVertex& eMax, PerVertex& eLo,
              PerVertex& eHi)
{
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    // Edges: per row t = tb, an edge spanning tb crosses at s0 + (tb - t0) * slope, kept within
    // the edge's own span of s: when an edge's ends have t a few ulps apart the slope is noise,
    // and unclamped the crossing landed far outside the polygon (one triangle blocked 25k rays
    // up to 0.39 m from it). The crossing starts from the end of smaller magnitude (whichever way
    // the polygon walks the edge, so two triangles sharing it compute it bit for bit). An edge
    // along the row (both t equal) is left out: the edges at its ends reach the row too and bring
    // its ends.
    for (int i = 0, k = count - 1; i < count; k = i++) {
        const __m256 flat = _mm256_cmp_ps(pt[k], pt[i], _CMP_EQ_OQ);
        const __m256 fromI = _mm256_cmp_ps(magnitude[i], magnitude[k], _CMP_LT_OQ);
        eSlope[i] = _mm256_div_ps(_mm256_sub_ps(ps[i], ps[k]), _mm256_sub_ps(pt[i], pt[k]));
        eBase[i] = _mm256_blendv_ps(ps[k], ps[i], fromI);
        eT0[i] = _mm256_blendv_ps(pt[k], pt[i], fromI);
        eLo[i] = _mm256_min_ps(ps[k], ps[i]);
        eHi[i] = _mm256_max_ps(ps[k], ps[i]);
        eMin[i] = _mm256_min_ps(pt[k], pt[i]);
        eMax[i] = _mm256_max_ps(pt[k], pt[i]);
        widen(eMin[i], eMax[i], widenT);
        eMin[i] = _mm256_blendv_ps(eMin[i], inf, flat);
    }
}

/// Per lane, the interval [lo, hi] of s inside the polygon along row t = tb: the clamped
/// crossings of the edges that span the row (empty where none does).
[[gnu::always_inline]] SIGHTLINE_AVX2 inline void
rowInterval(__m256 tb, int count, const PerVertex& eBase, const PerVertex& eT0, const PerVertex& eSlope,
            const PerVertex& eMin, const PerVertex& eMax, const PerVertex& eLo, const PerVertex& eHi, __m256& lo,
            __m256& hi)
{
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    const __m256 negInf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
    for (int e = 0; e < count; ++e) {
        const __m256 spans = _mm256_and_ps(_mm256_cmp_ps(tb, eMin[e], _CMP_GE_OQ), _mm256_cmp_ps(tb, eMax[e], _CMP_LE_OQ));
        const __m256 x = _mm256_fmadd_ps(_mm256_sub_ps(tb, eT0[e]), eSlope[e], eBase[e]);
        // max/min return their second operand when the first is NaN (a 0 * inf slope).
        const __m256 clamped = _mm256_min_ps(_mm256_max_ps(x, eLo[e]), eHi[e]);
        lo = _mm256_min_ps(_mm256_blendv_ps(inf, clamped, spans), lo);
        hi = _mm256_max_ps(_mm256_blendv_ps(negInf, clamped, spans), hi);
    }
}

/// Per lane, row b's bits: the samples of the row inside the polygon's backprojection, widened
/// by widenS; none outside the lane's rows [b0, b1].
[[gnu::always_inline]] SIGHTLINE_AVX2 inline __m256i
rowRun(const LaneGroup& lanes, int b, int count, const PerVertex& eBase, const PerVertex& eT0, const PerVertex& eSlope,
       const PerVertex& eMin, const PerVertex& eMax, const PerVertex& eLo, const PerVertex& eHi, __m256 widenS, int na,
       __m256i b0, __m256i b1)
{
    const __m256i oneI = _mm256_set1_epi32(1), twoI = _mm256_set1_epi32(2);
    const __m256 tb = _mm256_broadcast_ss(&lanes.rowCentres[b]);
    __m256 lo = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    __m256 hi = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
    rowInterval(tb, count, eBase, eT0, eSlope, eMin, eMax, eLo, eHi, lo, hi);
    __m256i a0, a1;
    widen(lo, hi, widenS);
    sampleRange(lo, hi, na, a0, a1);
    const __m256i row = _mm256_set1_epi32(b);
    const __m256i outside = _mm256_or_si256(
        _mm256_or_si256(_mm256_cmpgt_epi32(b0, row), _mm256_cmpgt_epi32(row, b1)), _mm256_cmpgt_epi32(a0, a1));
    // Bits a0..a1: (2 << a1) - (1 << a0); for a1 = 31 the first term wraps to 0, still right.
    const __m256i run = _mm256_sub_epi32(_mm256_sllv_epi32(twoI, a1), _mm256_sllv_epi32(oneI, a0));
    return _mm256_andnot_si256(outside, run);
}

/// ORs a packed word (lanes 0-3 in packedLo, 4-7 in packedHi) into word `word` of every lane's row.
[[gnu::always_inline]] SIGHTLINE_AVX2 inline void orWord(int word, const LaneGroup& lanes, __m256i packedLo,
                                                        __m256i packedHi)
{
    alignas(32) std::uint64_t out[kLanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(out), packedLo);
    _mm256_store_si256(reinterpret_cast<__m256i*>(out + 4), packedHi);
    // Every lane: an inactive lane's bits are zero, and its row is valid (LaneGroup).
    for (int l = 0; l < kLanes; ++l)
        lanes.rows[l][word] |= out[l];
}

/// ORs row b's bits into the rows of the lanes in `written` (those that have any), at the row's
/// bit position.
[[gnu::always_inline]] SIGHTLINE_AVX2 inline void scatterRow(__m256i masked, unsigned written, int b, int na,
                                                            const LaneGroup& lanes, std::uint32_t (&bits)[kLanes])
{
    _mm256_store_si256(reinterpret_cast<__m256i*>(bits), masked);
    const int position = b * na, wordOfRow = position >> 6, shift = position & 63;
    for (; written; written &= written - 1) {
        const int l = std::countr_zero(written);
        std::uint64_t* out = lanes.rows[l];
        out[wordOfRow] |= std::uint64_t(bits[l]) << shift;
        if (shift + na > 64)
            out[wordOfRow + 1] |= std::uint64_t(bits[l]) >> (64 - shift);
    }
}

/// 32 columns: pairs up the kept rows 2w and 2w + 1 of rows rowMin..rowMax into word w of every
/// lane's row.
[[gnu::always_inline]] SIGHTLINE_AVX2 inline void pairRows(std::uint32_t (&rowBits)[34][kLanes], int rowMin,
                                                          int rowMax, const LaneGroup& lanes)
{
    const int w0 = rowMin >> 1, w1 = rowMax >> 1;
    if (rowMin & 1)
        _mm256_store_si256(reinterpret_cast<__m256i*>(rowBits[rowMin - 1]), _mm256_setzero_si256());
    if (!(rowMax & 1))
        _mm256_store_si256(reinterpret_cast<__m256i*>(rowBits[rowMax + 1]), _mm256_setzero_si256());
    alignas(32) std::uint64_t pair[kLanes];   // word w of each lane: rows 2w and 2w + 1
    for (int w = w0; w <= w1; ++w) {
        const __m256i lo = _mm256_load_si256(reinterpret_cast<const __m256i*>(rowBits[2 * w]));
        const __m256i hi = _mm256_load_si256(reinterpret_cast<const __m256i*>(rowBits[2 * w + 1]));
        // 64-bit lanes 0 1 4 5 in a, 2 3 6 7 in b; then in order.
        const __m256i a = _mm256_unpacklo_epi32(lo, hi), b = _mm256_unpackhi_epi32(lo, hi);
        _mm256_store_si256(reinterpret_cast<__m256i*>(pair), _mm256_permute2x128_si256(a, b, 0x20));
        _mm256_store_si256(reinterpret_cast<__m256i*>(pair + 4), _mm256_permute2x128_si256(a, b, 0x31));
        // Every lane: an inactive lane's bits are zero, and its row is valid (LaneGroup).
        for (int l = 0; l < kLanes; ++l)
            lanes.rows[l][w] |= pair[l];
    }
}

/// The kernel. `Proven`: the caller's coarse bound (backprojectRowsAvx2) already keeps every
/// lane within the budget and the polygon is not closed, so no per-lane bound, no widening, and
/// s and t without their residuals (their rounding is not stretched in ray terms).
template <bool Proven>
SIGHTLINE_AVX2 int rows(const FloatPolygon& polygon, const LaneGroup& lanes, unsigned activeLanes, int na, int nb,
                        unsigned* fallback)
{
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    const __m256 negInf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());

    __m256 ps[kMaxPolygon], pt[kMaxPolygon], magnitude[kMaxPolygon], factor[kMaxPolygon], rayS[kMaxPolygon],
        rayT[kMaxPolygon];
    __m256 tMin = inf, tMax = negInf, rayMaxS = _mm256_setzero_ps(), rayMaxT = rayMaxS;
    backprojectVertices<Proven>(polygon, lanes, ps, pt, magnitude, factor, rayS, rayT, tMin, tMax, rayMaxS, rayMaxT);
    __m256 widenS = _mm256_setzero_ps(), widenT = widenS;
    if constexpr (!Proven) {
        // In metres, with the row centres' and the jitter shift's rounding (2), times 1.001 for
        // the approximate 1 / k; samples misclassified lie within it of the exact boundary.
        const __m256 unit = _mm256_set1_ps(1.001f * kFloatUnit);
        __m256 slackS = _mm256_setzero_ps(), slackT = slackS, kMin = inf;
        const __m256 band = errorBand(polygon, lanes, rayS, rayT, factor, rayMaxS, rayMaxT, unit, slackS, slackT, kMin);
        unsigned over = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(band, _mm256_set1_ps(lanes.bandBudget), _CMP_NLE_UQ)));
        if (over & activeLanes) {
            // A lane whose backprojection, widened by its source-plane error, holds no sample
            // needs no proof: nothing to set, whatever the rounding (most lanes over the budget
            // are occluders far to the side of their receiver sample).
            if (!polygon.closed)
                sourcePlaneError(polygon.count, rayS, rayT, factor, unit, slackS, slackT, kMin);
            over &= ~holdingNoSample(polygon.count, ps, tMin, tMax, slackS, slackT, na, nb);
        }
        *fallback = over & activeLanes;
        activeLanes &= ~over;
        if (!activeLanes)
            return 0;
        if (polygon.closed)
            widenS = slackS, widenT = slackT;
    }

    __m256i b0, b1;
    int rowMin, rowMax;
    rowRange(activeLanes, nb, widenT, tMin, tMax, b0, b1, rowMin, rowMax);
    if (rowMin > rowMax)
        return std::popcount(activeLanes);

    const int count = polygon.count;
    __m256 eBase[kMaxPolygon], eT0[kMaxPolygon], eSlope[kMaxPolygon], eMin[kMaxPolygon], eMax[kMaxPolygon],
        eLo[kMaxPolygon], eHi[kMaxPolygon];
    edgeCrossings(count, ps, pt, magnitude, widenT, eBase, eT0, eSlope, eMin, eMax, eLo, eHi);

    // Source rows that tile 64-bit words: each lane ORs a word once, not a row at a time.
    // 32 columns (the usual 32 x 32 source): rows 2w and 2w + 1 are the halves of word w; their
    // bits are kept and paired up once the rows are done. Narrower widths that divide 64 (16 for
    // 256 samples) gather a word's rows in 64-bit lanes as they go, which beats scattering (for
    // 32 columns it lost to pairing; README, "Measured"). Other widths scatter row by row.
    const bool paired = na == 32;
    const bool packed = !paired && 64 % na == 0;
    const int rowsPerWord = packed ? 64 / na : 1;
    alignas(32) std::uint32_t rowBits[34][kLanes];   // paired: na == 32 means nb <= 32, and a row either side
    __m256i packedLo = _mm256_setzero_si256(), packedHi = _mm256_setzero_si256();   // lanes 0-3, 4-7
    int word = rowMin / rowsPerWord, slot = rowMin % rowsPerWord;
    alignas(32) std::uint32_t bits[kLanes];
    for (int b = rowMin; b <= rowMax; ++b) {
        const __m256i masked = rowRun(lanes, b, count, eBase, eT0, eSlope, eMin, eMax, eLo, eHi, widenS, na, b0, b1);
        if (paired) {
            _mm256_store_si256(reinterpret_cast<__m256i*>(rowBits[b]), masked);
            continue;
        }
        if (packed) {
            const __m128i shift = _mm_cvtsi32_si128(slot * na);
            packedLo = _mm256_or_si256(packedLo, _mm256_sll_epi64(_mm256_cvtepu32_epi64(_mm256_castsi256_si128(masked)), shift));
            packedHi = _mm256_or_si256(packedHi, _mm256_sll_epi64(_mm256_cvtepu32_epi64(_mm256_extracti128_si256(masked, 1)), shift));
            if (++slot == rowsPerWord || b == rowMax) {
                orWord(word, lanes, packedLo, packedHi);
                packedLo = packedHi = _mm256_setzero_si256();
                ++word, slot = 0;
            }
            continue;
        }
        const unsigned empty = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(masked, _mm256_setzero_si256()))));
        unsigned written = ~empty & 0xffu;
        if (!written)
            continue;
        scatterRow(masked, written, b, na, lanes, bits);
    }
    if (paired)
        pairRows(rowBits, rowMin, rowMax, lanes);
    return std::popcount(activeLanes);
}

} // namespace

SIGHTLINE_AVX2 void sampleRangeFloat8(const float lo[kLanes], const float hi[kLanes], int n, int first[kLanes],
                                      int last[kLanes])
{
    __m256i f, l;
    sampleRange(_mm256_loadu_ps(lo), _mm256_loadu_ps(hi), n, f, l);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(first), f);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(last), l);
}

SIGHTLINE_AVX2 int backprojectRowsAvx2(const FloatPolygon& polygon, const LaneGroup& lanes, unsigned active, int na,
                                       int nb, unsigned* fallback)
{
    const unsigned activeLanes = active & 0xffu;
    *fallback = 0;
    if (!activeLanes)
        return 0;
    // A coarse bound on the per-lane one, from the largest coordinates alone (|x - r| <= |x| +
    // |r|, |p| / k <= |r| / k + |x - r|, s and t without residuals): u (10 |x| + 15 |r| + 2) per
    // axis. It settles most calls; the rest take the per-lane proof.
    const float coarse = 1.001f * kFloatUnit *
                         ((10.0f * polygon.sReach + 15.0f * lanes.sReach + 2.0f) * lanes.metresPerS +
                          (10.0f * polygon.tReach + 15.0f * lanes.tReach + 2.0f) * lanes.metresPerT);
    if (!polygon.closed && coarse <= lanes.bandBudget)
        return rows<true>(polygon, lanes, activeLanes, na, nb, fallback);
    return rows<false>(polygon, lanes, activeLanes, na, nb, fallback);
}

#else

bool floatRowsAvailable() { return false; }
void sampleRangeFloat8(const float*, const float*, int, int*, int*) {}
int backprojectRowsAvx2(const FloatPolygon&, const LaneGroup&, unsigned active, int, int, unsigned* fallback)
{
    *fallback = active & 0xffu;   // no kernel: every lane takes the double path
    return 0;
}

#endif

} // namespace sightline::detail
