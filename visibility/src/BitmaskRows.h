#pragma once
// Internal to the CPU bitmask sampler: the exact per-row backprojection kernel (§4-5) for eight
// receiver samples at once, in single precision with AVX2.
//
// Each lane is one receiver sample. Per lane, the polygon's vertices are backprojected onto the
// source plane (one division each, none for parallel patches), its edges give, per source-sample
// row, the interval of columns inside, and the interval becomes a run of bits ((2 << last) - (1 <<
// first) in 32-bit lanes, so source grids up to 32 columns wide). The caller keeps the cases this
// kernel is not accurate or general enough for on the double-precision scalar path:
// - vertices close to a receiver sample's distance (the projection factor d_R / (d_R - d_X)
//   amplifies float rounding; the sampler sends an occluder to a lane group only where every
//   factor is <= kMaxFloatFactor);
// - vertices at or beyond a receiver sample's distance (they need clipping per sample);
// - source grids wider than 32 columns.

#include <cstdint>
#include <vector>

namespace sightline::detail {

/// Largest projection factor the float kernel accepts: the backprojection's rounding error is
/// about this times the float epsilon of the source coordinates (16 * 6e-8 = 1e-6 of the patch).
constexpr double kMaxFloatFactor = 16.0;

constexpr int kLanes = 8;
constexpr int kMaxPolygon = 8;

/// A convex polygon in source coordinates (s, t, d), every vertex strictly closer to the source
/// plane than any receiver sample of the lanes.
struct FloatPolygon {
    alignas(32) float s[kMaxPolygon];
    float t[kMaxPolygon];
    float d[kMaxPolygon];
    /// Parallel patches: every lane's receiver sample has the same distance d_R, and k holds each
    /// vertex's projection factor d_R / (d_R - d), computed once (in double) instead of per lane.
    float k[kMaxPolygon];
    int count = 0;
    bool sharedFactor = false;
};

/// The box {sMin, sMax, tMin, tMax} of the polygon's backprojections from four receiver points
/// (s, t, d), each farther from the source plane than every vertex. Single precision: the caller
/// pads the box by the rounding (relative error about kMaxFloatFactor times the float epsilon).
void backprojectedBounds(const FloatPolygon& polygon, const float rs[4], const float rt[4], const float rd[4],
                         float out[4]);

/// Up to eight receiver samples in source coordinates and their rows in the hidden-samples map.
struct LaneGroup {
    alignas(32) float s[kLanes];
    alignas(32) float t[kLanes];
    alignas(32) float d[kLanes];
    alignas(32) float shiftS[kLanes] = {};   ///< decorrelated sampling: subtracted from the
    alignas(32) float shiftT[kLanes] = {};   ///< backprojection (SourceJitter.h)
    bool shifted = false;                ///< shiftS, shiftT are not all zero
    /// t of each source row's samples, (b + 0.5f) / nb in float (rowCentres in this header).
    const float* rowCentres = nullptr;
    /// Each lane's row, valid (possibly a scratch row) for every lane: inactive lanes may have
    /// zeros ORed into theirs.
    std::uint64_t* rows[kLanes] = {};
};

/// The t coordinate of source row b's samples, for b < nb, as the kernel compares them.
inline std::vector<float> rowCentres(int nb)
{
    std::vector<float> t(static_cast<std::size_t>(nb));
    for (int b = 0; b < nb; ++b)
        t[std::size_t(b)] = (float(b) + 0.5f) / float(nb);
    return t;
}

/// Whether this CPU runs the AVX2 kernel.
bool floatRowsAvailable();

/// ORs into each active lane's row (bit l of `active`: lane l) the source samples of the na x nb
/// grid (na <= 32) inside the polygon's backprojection from that lane's receiver sample. Returns
/// the number of active lanes.
int backprojectRowsAvx2(const FloatPolygon& polygon, const LaneGroup& lanes, unsigned active, int na, int nb);

} // namespace sightline::detail
