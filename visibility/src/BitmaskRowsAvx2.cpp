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

SIGHTLINE_AVX2 int backprojectRowsAvx2(const FloatPolygon& polygon, const LaneGroup& lanes, unsigned active, int na,
                                       int nb)
{
    const unsigned activeLanes = active & 0xffu;
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
        const __m256 k = polygon.sharedFactor ? _mm256_set1_ps(polygon.k[i])
                                              : _mm256_div_ps(rd, _mm256_sub_ps(rd, _mm256_set1_ps(polygon.d[i])));
        ps[i] = _mm256_fmadd_ps(_mm256_sub_ps(_mm256_set1_ps(polygon.s[i]), rs), k, rs);
        pt[i] = _mm256_fmadd_ps(_mm256_sub_ps(_mm256_set1_ps(polygon.t[i]), rt), k, rt);
        if (lanes.shifted) {
            ps[i] = _mm256_sub_ps(ps[i], shiftS);
            pt[i] = _mm256_sub_ps(pt[i], shiftT);
        }
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
    // Inactive lanes get an empty row range, so their bits stay zero.
    const __m256i laneBit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i on = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(activeLanes)), laneBit), laneBit);
    b0 = _mm256_blendv_epi8(_mm256_set1_epi32(nb), b0, on);
    const int rowMin = horizontalMin(b0), rowMax = horizontalMax(_mm256_blendv_epi8(_mm256_set1_epi32(-1), b1, on));
    if (rowMin > rowMax)
        return std::popcount(activeLanes);

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
    // Source rows that tile 64-bit words: each lane ORs a word once, not a row at a time.
    // 32 columns (the usual 32 x 32 source): rows 2w and 2w + 1 are the halves of word w; their
    // bits are kept and paired up once the rows are done. Narrower widths that divide 64 (16 for
    // 256 samples; 1.78 -> 1.41 s CPU against scattering, on 11 runs of the 128x128 wall) gather
    // a word's rows in 64-bit lanes as they go (for 32 columns that was 5% slower than pairing).
    // Other widths scatter row by row.
    const bool paired = na == 32;
    const bool packed = !paired && 64 % na == 0;
    const int rowsPerWord = packed ? 64 / na : 1;
    alignas(32) std::uint32_t rowBits[34][kLanes];   // paired: na == 32 means nb <= 32, and a row either side
    __m256i packedLo = _mm256_setzero_si256(), packedHi = _mm256_setzero_si256();   // lanes 0-3, 4-7
    int word = rowMin / rowsPerWord, slot = rowMin % rowsPerWord;
    alignas(32) std::uint32_t bits[kLanes];
    for (int b = rowMin; b <= rowMax; ++b) {
        const __m256 tb = _mm256_broadcast_ss(&lanes.rowCentres[b]);
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
        if (paired) {
            _mm256_store_si256(reinterpret_cast<__m256i*>(rowBits[b]), masked);
            continue;
        }
        if (packed) {
            const __m128i shift = _mm_cvtsi32_si128(slot * na);
            packedLo = _mm256_or_si256(packedLo, _mm256_sll_epi64(_mm256_cvtepu32_epi64(_mm256_castsi256_si128(masked)), shift));
            packedHi = _mm256_or_si256(packedHi, _mm256_sll_epi64(_mm256_cvtepu32_epi64(_mm256_extracti128_si256(masked, 1)), shift));
            if (++slot == rowsPerWord || b == rowMax) {
                alignas(32) std::uint64_t out[kLanes];
                _mm256_store_si256(reinterpret_cast<__m256i*>(out), packedLo);
                _mm256_store_si256(reinterpret_cast<__m256i*>(out + 4), packedHi);
                // Every lane: an inactive lane's bits are zero, and its row is valid (LaneGroup).
                for (int l = 0; l < kLanes; ++l)
                    lanes.rows[l][word] |= out[l];
                packedLo = packedHi = _mm256_setzero_si256();
                ++word, slot = 0;
            }
            continue;
        }
        const unsigned empty = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(masked, _mm256_setzero_si256()))));
        unsigned written = ~empty & 0xffu;
        if (!written)
            continue;
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
    if (paired) {
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
    return std::popcount(activeLanes);
}

#else

bool floatRowsAvailable() { return false; }
int backprojectRowsAvx2(const FloatPolygon&, const LaneGroup&, unsigned, int, int) { return 0; }

#endif

} // namespace sightline::detail
