#pragma once
// Internal to the CPU bitmask sampler: the exact per-row backprojection kernel (§4-5) for eight
// receiver samples at once, in single precision with AVX2.
//
// Each lane is one receiver sample. Per lane, the polygon's vertices are backprojected onto the
// source plane (one division each, none for parallel patches), its edges give, per source-sample
// row, the interval of columns inside, and the interval becomes a run of bits ((2 << last) - (1 <<
// first) in 32-bit lanes, so source grids up to 32 columns wide).
//
// Exact by docs/design.md §2's contract, as a filtered predicate: per lane the kernel bounds how far
// its float answer can stray from the double one (a forward error analysis of its own arithmetic
// and of its inputs' rounding to float, carried through the projection: per vertex
// u (k (|r| + |x|) + (2k + 1) |p - r|), plus the crossings' and comparisons' rounding), widens
// every interval by that bound, and checks that the band of samples it may then get wrong is
// narrower, as a distance between the ray and the occluder's boundary in metres, than
// LaneGroup::bandBudget (well inside the contract's 1e-5 m ties). A lane it cannot prove is
// returned in `fallback` for the double-precision path. The widening also keeps meshes closed
// (a sample on an edge two triangles share falls in at least one of them, whichever path each
// takes), which watertight culling relies on.
//
// The caller keeps on the double path, before the kernel is asked:
// - vertices close to a receiver sample's distance (projection factors d_R / (d_R - d_X) above
//   kMaxFloatFactor);
// - vertices at or beyond a receiver sample's distance (they need clipping per sample);
// - source grids wider than 32 columns.

#include <cstdint>
#include <vector>

namespace sightline::detail {

/// Largest projection factor the float kernel accepts: the backprojection's rounding error is
/// about this times the float epsilon of the source coordinates (16 * 6e-8 = 1e-6 of the patch).
constexpr double kMaxFloatFactor = 16.0;

/// Float's unit roundoff, 2^-24.
constexpr float kFloatUnit = 1.0f / 16777216.0f;

constexpr int kLanes = 8;
/// A triangle clipped to the slab between the patches: at most two cuts, so five vertices.
constexpr int kMaxPolygon = 5;

/// A convex polygon in source coordinates (s, t, d), every vertex strictly closer to the source
/// plane than any receiver sample of the lanes. Each coordinate is a float and its rounding
/// residual (x = s + sLo to about 2^-48 of x): the kernel takes differences of the pairs.
struct FloatPolygon {
    alignas(32) float s[kMaxPolygon];
    float t[kMaxPolygon];
    float d[kMaxPolygon];
    /// Parallel patches: every lane's receiver sample has the same distance d_R, and k holds each
    /// vertex's projection factor d_R / (d_R - d), computed once (in double) instead of per lane.
    float k[kMaxPolygon];
    float sLo[kMaxPolygon];
    float tLo[kMaxPolygon];
    float dLo[kMaxPolygon];
    /// The largest |s| and |t| of the vertices (the kernel's coarse bound).
    float sReach = 0.0f, tReach = 0.0f;
    int count = 0;
    bool sharedFactor = false;
    /// Part of a closed mesh, whose front faces culling may remove (§7): the kernel then widens
    /// its intervals by its error bound, so a sample on an edge this triangle shares with one
    /// taken by the double path falls in at least one of them. Elsewhere such a crack is only a
    /// tie.
    bool closed = false;
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
    /// Their rounding residuals (FloatPolygon).
    alignas(32) float sLo[kLanes];
    alignas(32) float tLo[kLanes];
    alignas(32) float dLo[kLanes];
    alignas(32) float shiftS[kLanes] = {};   ///< decorrelated sampling: subtracted from the
    alignas(32) float shiftT[kLanes] = {};   ///< backprojection (SourceJitter.h)
    bool shifted = false;                ///< shiftS, shiftT are not all zero
    /// t of each source row's samples, (b + 0.5f) / nb in float (rowCentres in this header).
    const float* rowCentres = nullptr;
    /// Each lane's row, valid (possibly a scratch row) for every lane: inactive lanes may have
    /// zeros ORed into theirs.
    std::uint64_t* rows[kLanes] = {};
    /// Metres per unit of source s and t (|u| and |v|), and the widest band of possibly
    /// misclassified samples, in metres between ray and boundary, the kernel may answer for.
    float metresPerS = 1.0f, metresPerT = 1.0f;
    float bandBudget = 0.0f;
    /// The largest |s| and |t| of the lanes' samples, valid or not (the kernel's coarse bound).
    float sReach = 0.0f, tReach = 0.0f;
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

/// The kernel's own sample-range rounding (SampleRange.h's, in AVX2), for eight intervals at
/// once: for tests that check the languages against each other. Needs floatRowsAvailable().
void sampleRangeFloat8(const float lo[kLanes], const float hi[kLanes], int n, int first[kLanes], int last[kLanes]);

/// ORs into each active lane's row (bit l of `active`: lane l) the source samples of the na x nb
/// grid (na <= 32) inside the polygon's backprojection from that lane's receiver sample. Lanes
/// whose answer the kernel cannot prove within the band budget are left alone and set in
/// `*fallback` (all of them where the CPU lacks AVX2). Returns the number of lanes answered.
int backprojectRowsAvx2(const FloatPolygon& polygon, const LaneGroup& lanes, unsigned active, int na, int nb,
                        unsigned* fallback);

} // namespace sightline::detail
