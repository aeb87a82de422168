#include "visibility/CpuBitmaskSampler.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "BitmaskRows.h"
#include "visibility/ExactSegment.h"
#include "visibility/RayCastSampler.h"
#include "visibility/ShaftGeometry.h"

namespace sightline {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

/// Receiver samples are processed in square tiles; a tile is the unit of parallel work, of
/// binning and of the narrowed shaft. 8x8 against 4x4 on the 128x128 wall receiver, 1024 source
/// samples: 27% more pairs (coarser narrowing) but a third less per-(occluder, tile) work, 122 ->
/// 105 ms.
constexpr int kTile = 8;

/// How an occluder is backprojected from a set of receiver samples, cheapest first.
enum class Path : std::uint8_t {
    Float,    ///< the single-precision kernel (BitmaskRows.h): well conditioned for every sample
    Double,   ///< double precision, every vertex closer to the source than every sample
    Clip,     ///< some vertex may reach a sample's distance: clipped per sample
};

/// A triangle clipped to the slab, ready for backprojection: vertices in source coordinates
/// (s, t, d) and the range of receiver samples its influence region covers.
struct Occluder {
    std::array<glm::dvec3, ClippedPolygon::kMaxVertices> vertices;
    int count = 0;
    int a0 = 0, a1 = -1, b0 = 0, b1 = -1;   ///< receiver sample range, inclusive
    double maxD = 0.0;                      ///< the largest vertex distance from the source plane
    /// Over the whole region. A flat receiver's tile may take a cheaper path over its own part
    /// (Setup::pathFor): an object standing on a floor needs clipping only near where it stands.
    Path path = Path::Clip;
    double cells = 0.0;                     ///< backprojected area from the region, in source cells
    /// Parallel patches: every receiver sample has the same distance d_R, so each vertex's
    /// projection factor d_R / (d_R - d_X) is one number per occluder, not one per pair.
    std::array<double, ClippedPolygon::kMaxVertices> factor;
};

/// What the per-tile loop reads of an occluder, stored in processing order so that a tile's walk
/// through its bin runs forwards through memory: an Occluder is ~600 bytes, and loading one was
/// the loop's largest stall (a quarter of its samples in perf on the 128x128 wall receiver).
struct TileOccluder {
    detail::FloatPolygon single;   // the vertices (and parallel factors) in float
    std::int16_t a0, a1, b0, b1;   // static_assert'ed below: receiver sides fit
    Path path;
    bool closed;                   // of a watertight instance (culling may trim it, §7)
    double maxD;
    const Occluder* occluder;      // the double-precision data
};
static_assert(kMaxReceiverSide <= 32767, "TileOccluder's sample range");

/// Per tile, occluders are processed largest first, each tested against the source samples the
/// tile's receiver samples still see (narrowed shaft); that set is recomputed every this many
/// occluders. Measured on the demo at 128x128 receiver samples: the conservatory floor 33.7M
/// pairs when only occluders under 8 source cells were tested, 5.7M testing all (the furniture
/// behind the wall is large but wholly hidden from most tiles); refreshing every 32 rather than
/// 256 occluders takes the wall receiver from 15.8M to 15.2M.
constexpr int kNarrowRefresh = 32;

/// Source samples that some receiver sample of a tile still sees: as a box of sample-centre
/// coordinates (empty when min > max), a quick first test, and as the set itself. Leaves and
/// grilles leave scattered holes whose box is nearly the whole source; the set still rejects an
/// occluder whose backprojection covers no open sample (demo, 1024 source samples: pairs 1.40M ->
/// 1.32M at 32x32 receiver samples, 20.6M -> 15.6M at 128x128).
struct SourceBox {
    double sMin = 1.0, sMax = 0.0, tMin = 1.0, tMax = 0.0;
    std::array<std::uint64_t, kMaxSourceSamples / 64> open{};
    bool empty() const { return sMin > sMax; }
    /// Whether any open sample has a bit index in [first, last].
    bool anyOpen(int first, int last) const
    {
        const int w0 = first >> 6, w1 = last >> 6;
        const std::uint64_t lo = ~std::uint64_t(0) << (first & 63);
        const std::uint64_t hi = ~std::uint64_t(0) >> (63 - (last & 63));
        if (w0 == w1)
            return (open[std::size_t(w0)] & lo & hi) != 0;
        if (open[std::size_t(w0)] & lo)
            return true;
        for (int w = w0 + 1; w < w1; ++w)
            if (open[std::size_t(w)])
                return true;
        return (open[std::size_t(w1)] & hi) != 0;
    }
};

/// The float kernel answers a lane only when the samples it may get wrong lie within this many
/// metres (ray to occluder boundary) of the exact answer's boundary: well inside the contract's
/// ties (1e-5 m), so nothing it answers can be a non-tie disagreement (BitmaskRows.h).
constexpr double kFloatBandBudget = 6e-6;

/// Auto picks RayCast when estimated pairs exceed this many times the rays. Scalar kernel: on the
/// demo a pair costs about half a ray (36 ns against 72 ns wall time on 2 cores, 1024 source
/// samples). SIMD kernel, estimates against measured times (2 cores): demo at 128 sources, 12.7
/// pairs per ray, Embree 14.0 ms, bitmask 20.6; at 256, 6.3 pairs per ray, 27.2 against 21.5;
/// dense mesh, 9.9 pairs per ray, 62 against 137 ms. The crossover lies near 8; 6 leans towards
/// ray casting, which is never slower than itself.
constexpr double kPairsPerRay = 2.0;
constexpr double kPairsPerRayFloat = 6.0;
/// Between kPairsPerRayFloat and this many estimated pairs per ray, Auto measures both methods on
/// one tile in kProbeStride each and finishes with the faster (the estimate does not see the
/// narrowed shaft). Measured, 1024 -> 64 source samples: demo at 32x32 receiver samples, 6.4 to
/// 25 estimated pairs per ray, bitmask 13.8 against Embree 24.2 ms at 256 sources and 10.9
/// against 8.0 at 64; at 128x128 receiver samples, 114 against 396 ms at 256 sources and 84
/// against 131 at 64 (25 per ray, beyond the band: Embree); the conservatory floor at 128x128,
/// 7.5 per ray at 1024 sources: bitmask 895 against Embree 271 ms.
constexpr double kProbePairsPerRay = 20.0;
constexpr std::uint32_t kProbeStride = 8;
/// A probe's choice serves this many later calls with the same grids before Auto times again.
constexpr int kProbeReuse = 7;
/// Below 64x64 receiver samples the probe's own cost (a batch of each method) is a large part of
/// the answer (demo at 32x32, 128 sources: 17.4 ms probed against 12.4 by Embree alone): the
/// estimate decides there.
constexpr int kProbeMinSamples = 64 * 64;
/// The probe needs every triangle binned to its tiles first (about estimated pairs / 64 entries,
/// 4 bytes each): above this many, the estimate decides. The conservatory floor at 512x512
/// samples estimates 2G pairs (32M entries, 0.27 s to bin) and the bitmask answers in 1.1 s
/// against Embree's 5 s.
constexpr std::uint64_t kProbeMaxBinEntries = std::uint64_t(40) << 20;

/// Below this many small triangles in the shaft, Auto keeps to the plain bitmask (a BVH build and
/// a ray pass cost more than they save).
constexpr std::size_t kHybridMinSmallTriangles = 500;

/// Sets bits first..last (inclusive) of a row of 64-bit words.
void setBitRange(std::uint64_t* words, int first, int last)
{
    int w0 = first >> 6, w1 = last >> 6;
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

/// Index range of samples at (k + 0.5) / n strictly inside (lo, hi), clamped to [0, n).
/// Samples exactly on the boundary are grazing; they count as inside (either answer is allowed).
inline void sampleRange(double lo, double hi, int n, int& first, int& last)
{
    // floor/ceil by truncation: std::floor is a library call on baseline x86-64 and this runs
    // several times per (triangle, receiver sample) pair. Clamping first keeps the int in range.
    const double x0 = std::clamp(lo * n - 0.5, -2.0, double(n) + 1.0);
    const double x1 = std::clamp(hi * n - 0.5, -2.0, double(n) + 1.0);
    const int c = int(x0);
    const int f = int(x1);
    first = std::max(0, c + (double(c) < x0));   // ceil
    last = std::min(n - 1, f - (double(f) > x1));  // floor
}

struct Setup {
    ShaftFrames frames;
    int S, na, nb;                         // source grid
    int rna, rnb;                          // receiver grid
    const HoughMaskTable* table = nullptr;      // Table mode; exact when null
    std::vector<glm::dvec3> receiverInSource;   // (s, t, d) of each receiver sample in the source frame
    std::array<glm::dvec3, 4> sourceCornersInReceiver;
    double minReceiverDistance = 0.0;      // min over receiver of d_source
    bool parallel = false;                 // the receiver's distance from the source plane is constant
    double receiverDistance = 0.0;         // that distance, when parallel
    glm::dvec3 receiverCentre{0.0};        // in the source frame
    bool floatKernel = false;              // the SIMD kernel may take well-conditioned occluders
    bool jittered = false;
    std::vector<glm::dvec2> jitterShift;   // per receiver sample: its source grid's offset in (s, t)
    std::vector<float> receiverS, receiverT, receiverD;   // receiverInSource in float
    std::vector<float> rowCentres = detail::rowCentres(nb);   // the SIMD kernel's source rows
    double metresPerS = 1.0, metresPerT = 1.0;             // |u|, |v| of the source
    // A bumpy receiver (§8): receiverInSource holds the displaced samples, and influence regions
    // are projected onto the receiver-frame planes d = levels[0] (lowest bump) and d = levels[1]
    // (highest). Flat: the receiver plane alone, d = 0.
    bool bumpy = false;
    std::array<double, 2> levels{0.0, 0.0};
    int levelCount = 1;
    double bumpySourceMargin = 0.0;    // clip at d_source > this
    double bumpyReceiverLevel = 0.0;   // clip at d_receiver > this

    /// `displaced`: a bumpy receiver's sample positions (world space, by bit index); null: flat.
    Setup(const Patch& source, const Patch& receiver, const SourceJitter& jitter,
          const std::vector<glm::dvec3>* displaced)
        : frames(source, receiver), S(source.sampleCount()), na(source.na), nb(source.nb), rna(receiver.na),
          rnb(receiver.nb), jittered(jitter.enabled()), metresPerS(glm::length(source.u)),
          metresPerT(glm::length(source.v))
    {
        // Sample i seen from j lies at (s_i + dx, t_i + dy); testing the backprojection shifted
        // by (-dx, -dy) against the regular grid is the same test.
        jitterShift.resize(std::size_t(receiver.sampleCount()));
        for (int j = 0; j < receiver.sampleCount(); ++j) {
            const glm::dvec2 o = jitter.offset(j);
            jitterShift[std::size_t(j)] = {o.x / na, o.y / nb};
        }
        receiverInSource.resize(std::size_t(receiver.sampleCount()));
        for (int j = 0; j < receiver.sampleCount(); ++j)
            receiverInSource[std::size_t(j)] =
                frames.source.coordinates(displaced ? (*displaced)[std::size_t(j)] : receiver.sample(j));
        minReceiverDistance = 1e300;
        for (int k = 0; k < 4; ++k) {
            const glm::dvec3 sc = source.corner + double(k & 1) * source.u + double(k >> 1) * source.v;
            sourceCornersInReceiver[std::size_t(k)] = frames.receiver.coordinates(sc);
            const glm::dvec3 rc = receiver.corner + double(k & 1) * receiver.u + double(k >> 1) * receiver.v;
            minReceiverDistance = std::min(minReceiverDistance, frames.source.coordinates(rc).z);
        }
        receiverCentre = frames.source.coordinates(receiver.centre());
        double maxReceiverDistance = 0.0;
        for (int k = 0; k < 4; ++k) {
            const glm::dvec3 rc = receiver.corner + double(k & 1) * receiver.u + double(k >> 1) * receiver.v;
            maxReceiverDistance = std::max(maxReceiverDistance, frames.source.coordinates(rc).z);
        }
        parallel = maxReceiverDistance - minReceiverDistance <= 1e-12 * maxReceiverDistance;
        receiverDistance = receiverCentre.z;
        if (displaced)
            setBumps(*displaced);
        for (const glm::dvec3& r : receiverInSource) {
            receiverS.push_back(float(r.x));
            receiverT.push_back(float(r.y));
            receiverD.push_back(float(r.z));
        }
    }

    /// A bumpy receiver (§8): every receiver sample is backprojected from its displaced position
    /// (receiverInSource), so the quantities that assumed the plane are taken over those samples.
    void setBumps(const std::vector<glm::dvec3>& displaced)
    {
        bumpy = true;
        double lowest = 1e300, highest = -1e300;
        minReceiverDistance = 1e300;
        glm::dvec3 sum(0.0);
        for (std::size_t j = 0; j < displaced.size(); ++j) {
            minReceiverDistance = std::min(minReceiverDistance, receiverInSource[j].z);
            sum += receiverInSource[j];
            const double height = frames.receiver.coordinates(displaced[j]).z;
            lowest = std::min(lowest, height), highest = std::max(highest, height);
        }
        // The samples' distances from the source differ: no per-occluder projection factors.
        parallel = false;
        // Only sizes occluders (Hybrid, the narrowed shaft): any point closer than every sample.
        receiverCentre = sum / double(displaced.size());
        receiverDistance = receiverCentre.z;
        levels = {lowest, highest};
        levelCount = highest > lowest ? 2 : 1;
        // DESIGN.md §2's end margin at the source end.
        bumpySourceMargin = kEndMarginMetres;
        // A segment's receiver-frame distance runs between its two ends, so no segment reaches
        // below the lowest bump (nor below the source, were a bump to rise past a source corner).
        // Parts beyond an individual sample are clipped per sample (backproject).
        bumpyReceiverLevel = lowest;
        for (const glm::dvec3& corner : sourceCornersInReceiver)
            bumpyReceiverLevel = std::min(bumpyReceiverLevel, corner.z);
    }

    /// The triangle clipped to the part of the slab any segment can reach (ShaftGeometry.h).
    ClippedPolygon clip(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const
    {
        if (!bumpy)
            return frames.clipToSlab(a, b, c);
        ClippedPolygon polygon;
        polygon.vertices[0] = glm::dvec3(a);
        polygon.vertices[1] = glm::dvec3(b);
        polygon.vertices[2] = glm::dvec3(c);
        polygon.count = 3;
        const PatchFrame& s = frames.source;
        const PatchFrame& r = frames.receiver;
        clipPolygon(polygon, s.dAxis, glm::dot(s.origin, s.dAxis) + bumpySourceMargin);
        if (polygon.count)
            clipPolygon(polygon, r.dAxis, glm::dot(r.origin, r.dAxis) + bumpyReceiverLevel);
        return polygon;
    }

    /// Clips, then bounds the influence region (§3): the projections of the clipped polygon from
    /// the four source corners onto the receiver plane, as a box of receiver samples. Where a
    /// vertex is not strictly closer to the receiver than a corner, the projection is undefined
    /// and the whole receiver is taken (conservative).
    ///
    /// A bumpy receiver (§8: "the projection from the light's corners has to be performed on a
    /// plane lying behind the receiver"): a sample at height h is hidden through X from source
    /// point Y only if it lies on line YX at height h. That point is a projective image of Y and
    /// of X with the same denominator d(Y) - d(X) > 0, so for each h it lies in the hull of the
    /// corner-vertex projections, and it is affine in h, so the projections onto the planes of
    /// the lowest and the highest bump bound every sample between them.
    bool prepare(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, Occluder& out) const
    {
        const ClippedPolygon polygon = clip(a, b, c);
        if (polygon.count < 3)
            return false;
        out.count = polygon.count;
        double sMin = 1e300, sMax = -1e300, tMin = 1e300, tMax = -1e300, maxD = -1e300;
        bool whole = false;
        for (int i = 0; i < polygon.count; ++i) {
            const glm::dvec3& x = polygon.vertices[std::size_t(i)];
            const glm::dvec3 inSource = frames.source.coordinates(x);
            out.vertices[std::size_t(i)] = inSource;
            maxD = std::max(maxD, inSource.z);
            const glm::dvec3 inReceiver = frames.receiver.coordinates(x);
            for (const glm::dvec3& corner : sourceCornersInReceiver) {
                const double denominator = corner.z - inReceiver.z;
                if (denominator <= 1e-12 * corner.z) {
                    whole = true;
                    continue;
                }
                for (int level = 0; level < levelCount; ++level) {
                    // Flat: levels[0] == 0 and the factor is corner.z / denominator, bit for bit.
                    const double k = (corner.z - levels[std::size_t(level)]) / denominator;
                    const double s = corner.x + (inReceiver.x - corner.x) * k;
                    const double t = corner.y + (inReceiver.y - corner.y) * k;
                    sMin = std::min(sMin, s), sMax = std::max(sMax, s);
                    tMin = std::min(tMin, t), tMax = std::max(tMax, t);
                }
            }
        }
        if (whole) {
            out.a0 = 0, out.a1 = rna - 1, out.b0 = 0, out.b1 = rnb - 1;
        } else {
            // Widen by a hair so that rounding never drops a sample on the region's boundary.
            const double pad = 1e-9;
            sampleRange(sMin - pad, sMax + pad, rna, out.a0, out.a1);
            sampleRange(tMin - pad, tMax + pad, rnb, out.b0, out.b1);
        }
        out.maxD = maxD;
        // Only the samples of the influence region are ever backprojected from, so on a flat
        // receiver the path is chosen for the region's nearest sample, not the receiver's.
        const bool regional = !bumpy && !whole && out.a0 <= out.a1 && out.b0 <= out.b1;
        out.path = pathFor(maxD, regional ? nearestSample(out.a0, out.a1, out.b0, out.b1) : minReceiverDistance);
        if (parallel)
            for (int i = 0; i < out.count; ++i)
                out.factor[std::size_t(i)] = receiverDistance / (receiverDistance - out.vertices[std::size_t(i)].z);
        // Sized from the region's farthest corner sample, beyond every vertex unless the occluder
        // crosses the whole region (such occluders go first, as the largest).
        out.cells = 1e300;
        if (regional) {
            glm::dvec3 farthest(0.0, 0.0, -1e300);
            for (const int rb : {out.b0, out.b1})
                for (const int ra : {out.a0, out.a1})
                    if (const glm::dvec3& r = receiverInSource[std::size_t(rb * rna + ra)]; r.z > farthest.z)
                        farthest = r;
            if (pathFor(maxD, farthest.z) != Path::Clip)
                out.cells = backprojectedCells(out, farthest);
        } else if (!whole && out.path != Path::Clip) {
            out.cells = backprojectedCells(out, receiverCentre);
        }
        return out.a0 <= out.a1 && out.b0 <= out.b1;
    }

    /// The occluder's vertices as float pairs, and its factors for parallel patches, for the
    /// float kernel (BitmaskRows.h) and the narrowing test's bounds (mayHitFloat).
    detail::FloatPolygon singlePrecision(const Occluder& o, bool closed) const
    {
        detail::FloatPolygon single;
        single.count = o.count;
        single.sharedFactor = parallel;
        single.closed = closed;
        for (int i = 0; i < o.count; ++i) {
            const glm::dvec3& x = o.vertices[std::size_t(i)];
            single.s[i] = float(x.x), single.sLo[i] = float(x.x - double(single.s[i]));
            single.t[i] = float(x.y), single.tLo[i] = float(x.y - double(single.t[i]));
            single.d[i] = float(x.z), single.dLo[i] = float(x.z - double(single.d[i]));
            single.k[i] = parallel ? float(o.factor[std::size_t(i)]) : 0.0f;
            single.sReach = std::max(single.sReach, std::abs(single.s[i]));
            single.tReach = std::max(single.tReach, std::abs(single.t[i]));
        }
        return single;
    }

    /// The distance from the source plane of the nearest receiver sample in [a0, a1] x [b0, b1]
    /// of a flat receiver: the distance is affine over the plane, so one of the box's corners.
    double nearestSample(int a0, int a1, int b0, int b1) const
    {
        const auto d = [&](int a, int b) { return receiverInSource[std::size_t(b * rna + a)].z; };
        return std::min(std::min(d(a0, b0), d(a1, b0)), std::min(d(a0, b1), d(a1, b1)));
    }

    /// The path for an occluder reaching `maxD` from the source, backprojected from receiver
    /// samples no nearer than `nearest`. Flat: the receiver-side clip margin already keeps every
    /// vertex out of the reference's end-point tolerance. Bumpy: only occluders wholly short of
    /// the nearest displaced sample, by more than that tolerance, skip the per-sample clip;
    /// those reaching into the bump range are clipped at each sample's own distance. Float:
    /// d_R / (d_R - d_X) <= kMaxFloatFactor for every sample and vertex.
    Path pathFor(double maxD, double nearest) const
    {
        if (maxD >= nearest - (bumpy ? 2.0 : 1.0) * kEndMarginMetres)
            return Path::Clip;
        if (floatKernel && maxD <= nearest * (1.0 - 1.0 / detail::kMaxFloatFactor))
            return Path::Float;
        return Path::Double;
    }

    /// Area of the backprojection from receiver point r (source coordinates, farther from the
    /// source than every vertex), in source-sample cells (shoelace).
    double backprojectedCells(const Occluder& o, const glm::dvec3& r) const
    {
        double area = 0.0, ps = 0.0, pt = 0.0;
        for (int i = 0; i <= o.count; ++i) {
            const glm::dvec3& x = o.vertices[std::size_t(i % o.count)];
            const double k = r.z / (r.z - x.z);
            const double s = r.x + (x.x - r.x) * k, t = r.y + (x.y - r.y) * k;
            if (i > 0)
                area += ps * t - s * pt;
            ps = s, pt = t;
        }
        return 0.5 * std::abs(area) * na * nb;
    }

    /// The common case, a backprojected triangle with some height: a scanline walk. Sorted by t,
    /// rows below the middle vertex lie between the long edge (0-2) and edge 0-1, the others
    /// between the long edge and edge 1-2; no per-row arrays, no per-edge row ranges. Crossings
    /// stay within their edge's span of s (a nearly flat edge's slope is rounding noise), and
    /// every interval is widened a hair (lower, upper).
    void triangleRows(const double* ps, const double* pt, int b0, int b1, std::uint64_t* mask) const
    {
        int i0 = 0, i1 = 1, i2 = 2;
        if (pt[i0] > pt[i1])
            std::swap(i0, i1);
        if (pt[i1] > pt[i2])
            std::swap(i1, i2);
        if (pt[i0] > pt[i1])
            std::swap(i0, i1);
        const double s0 = ps[i0], t0 = pt[i0], s1 = ps[i1], t1 = pt[i1], s2 = ps[i2], t2 = pt[i2];
        for (int b = b0; b <= b1; ++b) {
            const double tb = (b + 0.5) / nb;
            const double xLong = edgeCrossing(tb, s0, t0, s2, t2);
            double xShortLo, xShortHi;
            if (tb < t1 && t1 > t0) {
                xShortLo = xShortHi = edgeCrossing(tb, s0, t0, s1, t1);
            } else if (t2 > t1) {
                xShortLo = xShortHi = edgeCrossing(tb, s1, t1, s2, t2);
            } else {   // top edge along the row: both of its ends count
                xShortLo = std::min(s1, s2);
                xShortHi = std::max(s1, s2);
            }
            int a0, a1;
            sampleRange(lower(std::min(xLong, xShortLo)), upper(std::max(xLong, xShortHi)), na, a0, a1);
            if (a0 <= a1)
                setBitRange(mask, b * na + a0, b * na + a1);
        }
    }

    /// Where row t = tb crosses the edge (sa, ta) - (sb, tb_) (ta < tb_), kept within the edge's s.
    static double edgeCrossing(double tb, double sa, double ta, double sb, double tbEnd)
    {
        const double x = sa + (tb - ta) * ((sb - sa) / (tbEnd - ta));
        return std::clamp(x, std::min(sa, sb), std::max(sa, sb));
    }

    /// The double path's widening of an interval end: relative to the end itself (an occluder
    /// reaching near a receiver sample projects to 1e9 and more, and a slack relative to that
    /// would move its near edges by millimetres), far below any tie and far above rounding: two
    /// polygons sharing an edge compute it from different vertices, so a sample exactly on it
    /// could otherwise fall in neither.
    static double lower(double x) { return x - 1e-12 * (1.0 + std::abs(x)); }
    static double upper(double x) { return x + 1e-12 * (1.0 + std::abs(x)); }

    /// Table mode (§5): the AND of the Hough-table masks of the backprojection's edges, taken
    /// counter-clockwise so that the inside is on the left of every edge.
    void tableMask(const double* ps, const double* pt, int count, std::uint64_t* mask) const
    {
        double area = 0.0;
        for (int i = 0, k = count - 1; i < count; k = i++)
            area += ps[k] * pt[i] - ps[i] * pt[k];
        if (area == 0.0)
            return;   // degenerate: covers no area
        std::uint64_t inside[kMaxSourceSamples / 64];
        const int words = table->wordsPerMask();
        std::fill_n(inside, words, ~std::uint64_t(0));
        for (int e = 0; e < count; ++e) {
            int from = e, to = (e + 1) % count;
            if (area < 0.0)
                std::swap(from, to);
            if (ps[from] == ps[to] && pt[from] == pt[to])
                continue;
            const std::uint64_t* edge = table->lookup(ps[from], pt[from], ps[to], pt[to]);
            for (int w = 0; w < words; ++w)
                inside[w] &= edge[w];
        }
        for (int w = 0; w < words; ++w)
            mask[w] |= inside[w];
    }

    /// The box of source samples that at least one receiver sample in [a0, a1] x [b0, b1] still
    /// sees, from the map as it stands.
    SourceBox unblockedBox(const HiddenSampleMap& map, int a0, int a1, int b0, int b1) const
    {
        SourceBox box;
        auto& open = box.open;
        const int words = map.wordsPerRow();
        for (int b = b0; b <= b1; ++b)
            for (int a = a0; a <= a1; ++a) {
                const auto row = map.row(b * rna + a);
                for (int w = 0; w < words; ++w)
                    open[w] |= ~row[std::size_t(w)];
            }
        if (S % 64)
            open[words - 1] &= (std::uint64_t(1) << (S % 64)) - 1;
        int aMin = na, aMax = -1, bMin = nb, bMax = -1;
        if (na <= 64) {
            // Row by row: the rows with an open sample, and the union of their columns.
            std::uint64_t columns = 0;
            for (int b = 0; b < nb; ++b) {
                const int first = b * na, w = first >> 6, shift = first & 63;
                std::uint64_t bits = open[std::size_t(w)] >> shift;
                if (shift + na > 64)
                    bits |= open[std::size_t(w) + 1] << (64 - shift);
                if (na < 64)
                    bits &= (std::uint64_t(1) << na) - 1;
                if (bits) {
                    bMin = std::min(bMin, b), bMax = b;
                    columns |= bits;
                }
            }
            if (columns)
                aMin = std::countr_zero(columns), aMax = 63 - std::countl_zero(columns);
        } else {
            for (int w = 0; w < words; ++w)
                for (std::uint64_t bits = open[w]; bits; bits &= bits - 1) {
                    const int i = 64 * w + std::countr_zero(bits);
                    const int a = i % na, b = i / na;
                    aMin = std::min(aMin, a), aMax = std::max(aMax, a);
                    bMin = std::min(bMin, b), bMax = std::max(bMax, b);
                }
        }
        // Jittered samples lie up to half a cell from their cell centres.
        const double lo = jittered ? 0.0 : 0.5, hi = jittered ? 1.0 : 0.5;
        if (aMax >= 0) {
            box.sMin = (aMin + lo) / na, box.sMax = (aMax + hi) / na;
            box.tMin = (bMin + lo) / nb, box.tMax = (bMax + hi) / nb;
        }
        return box;
    }

    /// Whether the backprojection of `o` from any receiver sample in the tile spanned by the
    /// given samples can contain a sample of `box`. The backprojection of a point is an affine
    /// (parallel patches) or projective function of the receiver point, so on a flat receiver
    /// its extremes over the tile lie at the tile's corners; a bumpy receiver's tile is not
    /// planar, so there the caller passes every sample of the tile.
    bool mayHit(const Occluder& o, Path path, const int* samples, int sampleCount, const SourceBox& box) const
    {
        if (path == Path::Clip)
            return true;
        double sMin = 1e300, sMax = -1e300, tMin = 1e300, tMax = -1e300;
        for (int n = 0; n < sampleCount; ++n) {
            const glm::dvec3& r = receiverInSource[std::size_t(samples[n])];
            for (int i = 0; i < o.count; ++i) {
                const glm::dvec3& x = o.vertices[std::size_t(i)];
                const double k = parallel ? o.factor[std::size_t(i)] : r.z / (r.z - x.z);
                const double s = r.x + (x.x - r.x) * k, t = r.y + (x.y - r.y) * k;
                sMin = std::min(sMin, s), sMax = std::max(sMax, s);
                tMin = std::min(tMin, t), tMax = std::max(tMax, t);
            }
        }
        return boxMayHit(sMin, sMax, tMin, tMax, 1e-9, box);
    }

    /// mayHit for a float-path occluder on a flat receiver, from the four corners of a rectangle
    /// of samples, in single precision. The box is padded by the rounding of a backprojection
    /// with factors k up to kMaxFloatFactor: per vertex about u (2k |r| + (2k + 2) |p - r| + |p|)
    /// (BitmaskRows.h), under 70 u (|r| + |p|) = 4.2e-6 (|r| + |p|); 1e-5 taken.
    bool mayHitFloat(const detail::FloatPolygon& polygon, const std::array<int, 4>& corners, const SourceBox& box) const
    {
        float rs[4], rt[4], rd[4], bounds[4];
        double magnitude = 0.0;
        for (int c = 0; c < 4; ++c) {
            const std::size_t j = std::size_t(corners[std::size_t(c)]);
            rs[c] = receiverS[j], rt[c] = receiverT[j], rd[c] = receiverD[j];
            magnitude = std::max({magnitude, std::abs(double(rs[c])), std::abs(double(rt[c]))});
        }
        detail::backprojectedBounds(polygon, rs, rt, rd, bounds);
        magnitude += std::max({std::abs(bounds[0]), std::abs(bounds[1]), std::abs(bounds[2]), std::abs(bounds[3])});
        return boxMayHit(bounds[0], bounds[1], bounds[2], bounds[3], 1e-5 * (1.0 + magnitude), box);
    }

    /// Whether the box [sMin, sMax] x [tMin, tMax], widened by `pad`, holds an open sample.
    bool boxMayHit(double sMin, double sMax, double tMin, double tMax, double pad, const SourceBox& box) const
    {
        if (!(sMin <= box.sMax + pad && sMax >= box.sMin - pad && tMin <= box.tMax + pad && tMax >= box.tMin - pad))
            return false;
        // The samples whose positions can fall in [sMin, sMax] x [tMin, tMax]: centres (a + 0.5) / na,
        // or anywhere in their cell when jittered.
        // Ceil and floor by truncation, after clamping (as sampleRange): far backprojections
        // stay in int range, and no library call runs per (occluder, lane group).
        const auto range = [&](double lo, double hi, int n, int& first, int& last) {
            const double shift = jittered ? 0.0 : 0.5;
            const double x0 = std::clamp((lo - pad) * n - shift - (jittered ? 1.0 : 0.0), -2.0, double(n) + 1.0);
            const double x1 = std::clamp((hi + pad) * n - shift, -2.0, double(n) + 1.0);
            const int c = int(x0), f = int(x1);
            first = std::max(0, c + (double(c) < x0));
            last = std::min(n - 1, f - (double(f) > x1));
            return first <= last;
        };
        int aFirst, aLast, bFirst, bLast;
        if (!range(sMin, sMax, na, aFirst, aLast) || !range(tMin, tMax, nb, bFirst, bLast))
            return false;
        for (int b = bFirst; b <= bLast; ++b)
            if (box.anyOpen(b * na + aFirst, b * na + aLast))
                return true;
        return false;
    }

    /// ORs into `row` the source samples hidden by `occluder` from receiver sample j (§4-5), on
    /// the double-precision `path`.
    void backproject(const Occluder& occluder, Path path, int j, std::uint64_t* row) const
    {
        const glm::dvec3& r = receiverInSource[std::size_t(j)];
        if (path != Path::Clip) {
            backprojectPolygon(occluder.vertices.data(), occluder.count, r, jitterShift[std::size_t(j)], row,
                               parallel ? occluder.factor.data() : nullptr);
            return;
        }
        if (occluder.maxD < clipDistance(r.z)) {   // nothing to clip for this sample
            backprojectPolygon(occluder.vertices.data(), occluder.count, r, jitterShift[std::size_t(j)], row, nullptr);
            return;
        }
        const ClippedPolygon local = clippedFor(occluder, r.z);
        if (local.count >= 3)
            backprojectPolygon(local.vertices.data(), local.count, r, jitterShift[std::size_t(j)], row, nullptr);
    }

    /// Vertices at or beyond a receiver sample's own distance d cannot lie on its segments: the
    /// part of an occluder that can hide anything from it lies short of this (the end margin of
    /// ExactSegment.h). For a bumpy receiver this is where the parts beyond a displaced sample
    /// (farther from the source than the sample) stop blocking it.
    static double clipDistance(double d) { return d - kEndMarginMetres; }

    /// The occluder clipped for receiver samples at distance d from the source plane.
    static ClippedPolygon clippedFor(const Occluder& occluder, double d)
    {
        ClippedPolygon local;
        local.count = occluder.count;
        std::copy_n(occluder.vertices.begin(), occluder.count, local.vertices.begin());
        clipPolygon(local, glm::dvec3(0, 0, -1), -clipDistance(d));
        return local;
    }

    /// The backprojection from receiver point r (source coordinates) of a convex polygon whose
    /// vertices all lie in 0 < d < r.d, and the source samples inside it, row by row.
    /// `factors` (may be null): each vertex's r.d / (r.d - d), precomputed for parallel patches.
    void backprojectPolygon(const glm::dvec3* vertices, int count, const glm::dvec3& r, const glm::dvec2& shift,
                            std::uint64_t* mask, const double* factors) const
    {
        // Backprojection onto the source plane, in source (s, t).
        std::array<double, ClippedPolygon::kMaxVertices> ps, pt;
        double tMin = 1e300, tMax = -1e300;
        for (int i = 0; i < count; ++i) {
            const glm::dvec3& x = vertices[i];
            const double k = factors ? factors[i] : r.z / (r.z - x.z);
            ps[std::size_t(i)] = r.x + (x.x - r.x) * k - shift.x;
            pt[std::size_t(i)] = r.y + (x.y - r.y) * k - shift.y;
            tMin = std::min(tMin, pt[std::size_t(i)]);
            tMax = std::max(tMax, pt[std::size_t(i)]);
        }
        if (table) {
            tableMask(ps.data(), pt.data(), count, mask);
            return;
        }
        int b0, b1;
        sampleRange(lower(tMin), upper(tMax), nb, b0, b1);
        if (b0 > b1)
            return;
        if (count == 3 && tMax > tMin) {
            triangleRows(ps.data(), pt.data(), b0, b1, mask);
            return;
        }
        // Each row's line t = tb meets the convex polygon in one interval [lo, hi]. Walk every
        // edge over just the rows it spans (O(rows + edges), not O(rows x edges)).
        double lo[kMaxSourceSamples], hi[kMaxSourceSamples];
        std::fill(lo + b0, lo + b1 + 1, 1e300);
        std::fill(hi + b0, hi + b1 + 1, -1e300);
        for (int i = 0, k = count - 1; i < count; k = i++) {
            const double t0 = pt[std::size_t(k)], t1 = pt[std::size_t(i)];
            const double s0 = ps[std::size_t(k)], s1 = ps[std::size_t(i)];
            int r0, r1;
            sampleRange(lower(std::min(t0, t1)), upper(std::max(t0, t1)), nb, r0, r1);
            r0 = std::max(r0, b0);
            r1 = std::min(r1, b1);
            if (r0 > r1)
                continue;
            if (t0 == t1) {   // along a row: both ends count
                lo[r0] = std::min({lo[r0], s0, s1});
                hi[r0] = std::max({hi[r0], s0, s1});
                continue;
            }
            // From the lower end, whichever way the polygon walks the edge.
            const bool up = t0 < t1;
            const double sa = up ? s0 : s1, ta = up ? t0 : t1, sb = up ? s1 : s0, tbEnd = up ? t1 : t0;
            for (int row = r0; row <= r1; ++row) {
                const double x = edgeCrossing((row + 0.5) / nb, sa, ta, sb, tbEnd);
                lo[row] = std::min(lo[row], x);
                hi[row] = std::max(hi[row], x);
            }
        }
        for (int b = b0; b <= b1; ++b) {
            int a0, a1;
            sampleRange(lower(lo[b]), upper(hi[b]), na, a0, a1);
            if (a0 <= a1)
                setBitRange(mask, b * na + a0, b * na + a1);
        }
    }
};

bool rowFull(const std::uint64_t* row, int words, int S)
{
    for (int w = 0; w + 1 < words; ++w)
        if (row[w] != ~std::uint64_t(0))
            return false;
    const int rest = S - 64 * (words - 1);
    const std::uint64_t last = rest == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << rest) - 1;
    return row[words - 1] == last;
}

} // namespace

/// Buffers kept between calls: the editor samples ~20 times a second, and fresh multi-megabyte
/// allocations cost page faults every time (measured: 40 ms of a 75 ms call on the demo).
struct CpuBitmaskSampler::Workspace {
    std::vector<std::vector<Occluder>> found;             // per chunk of triangles
    std::vector<std::vector<std::uint32_t>> foundTriangle;
    std::vector<const Occluder*> occluders;
    std::vector<std::uint32_t> triangleOf;
    std::vector<char> small;
    std::vector<std::uint32_t> order;
    std::vector<TileOccluder> tileOccluders;              // in `order`
    std::vector<std::vector<std::uint32_t>> bins;         // positions in tileOccluders
};

namespace {

/// One sampling call, step by step. Holds references only; the map and stats are the caller's.
struct Pass {
    const Setup& setup;
    const WorldTriangles& triangles;
    const Patch& source;
    const Patch& receiver;
    const BitmaskOptions& options;
    HiddenSampleMap& map;
    BitmaskStats& stats;

    CpuBitmaskSampler::Workspace& work;
    // Views into the workspace:
    std::vector<const Occluder*>& occluders = work.occluders;   // the triangles in the shaft, in triangle order
    std::vector<std::uint32_t>& triangleOf = work.triangleOf;   // each occluder's triangle index
    std::vector<char>& small = work.small;                      // per occluder: left to the hybrid's ray pass

    const glm::vec3* triangle(std::size_t t) const { return &triangles.vertices[3 * t]; }

    /// Per instance: may watertight culling (§7) skip its front faces? Empty: no culling.
    std::vector<char> cullableInstance{};
    /// Per instance: a mesh flagged watertight (closed). Its triangles' float intervals are
    /// widened by their error bound whether or not culling trims it this call, so culling on and
    /// off give the same answer (BitmaskRows.h). Empty: none.
    std::vector<char> closedInstance{};
    std::array<glm::dvec3, 4> sourceCorners{};

    /// Per instance: bounds wholly outside the shaft's hull. Empty: unknown.
    std::vector<char> instanceOutside{};
    const ShaftHull* hull = nullptr;

    void init(std::vector<char> cullable, std::vector<char> outside, const ShaftHull& shaftHull)
    {
        cullableInstance = std::move(cullable);
        instanceOutside = std::move(outside);
        hull = &shaftHull;
        for (int k = 0; k < 4; ++k)
            sourceCorners[std::size_t(k)] = source.corner + double(k & 1) * source.u + double(k >> 1) * source.v;
    }

    /// Hierarchical shaft culling: the instance's bounds, then the triangle, against the hull
    /// (before any clipping).
    bool outsideShaft(std::size_t t) const
    {
        if (!instanceOutside.empty() && instanceOutside[triangles.instanceOf[t]])
            return true;
        return hull->excludes(triangle(t)[0], triangle(t)[1], triangle(t)[2]);
    }

    /// Watertight culling (§7): a front face, seen from all four source corners, of a cullable
    /// instance.
    bool culled(std::size_t t) const
    {
        if (cullableInstance.empty() || !cullableInstance[triangles.instanceOf[t]])
            return false;
        const glm::dvec3 a(triangle(t)[0]), b(triangle(t)[1]), c(triangle(t)[2]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        for (const glm::dvec3& corner : sourceCorners)
            if (glm::dot(n, corner - a) <= 0.0)
                return false;
        return true;
    }

    /// Auto's cost model: (triangle, receiver sample) pairs, estimated from every 32nd triangle
    /// that culling keeps, against the rays, each kind weighted by its measured cost.
    bool rayCastingIsCheaper(std::uint64_t* estimate) const
    {
        constexpr std::size_t kStride = 32;
        const std::uint64_t pairEstimate = tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, (triangles.size() + kStride - 1) / kStride, 64), std::uint64_t(0),
            [&](const auto& range, std::uint64_t sum) {
                Occluder o;
                for (std::size_t k = range.begin(); k != range.end(); ++k) {
                    const std::size_t t = k * kStride;
                    if (!outsideShaft(t) && !culled(t) && setup.prepare(triangle(t)[0], triangle(t)[1], triangle(t)[2], o))
                        sum += kStride * std::uint64_t(o.a1 - o.a0 + 1) * std::uint64_t(o.b1 - o.b0 + 1);
                }
                return sum;
            },
            std::plus<>());
        *estimate = pairEstimate;
        const double pairsPerRay = setup.floatKernel ? kPairsPerRayFloat : kPairsPerRay;
        return double(pairEstimate) > pairsPerRay * double(map.rayCount());
    }

    /// Clips and bounds every triangle (parallel) that culling (§7) does not remove, and keeps
    /// those in the shaft, in triangle order whatever the thread count.
    void prepareAll()
    {
        constexpr std::size_t kChunk = 2048;
        const std::size_t chunks = (triangles.size() + kChunk - 1) / kChunk;
        auto& found = work.found;
        auto& foundTriangle = work.foundTriangle;
        if (found.size() < chunks) {
            found.resize(chunks);
            foundTriangle.resize(chunks);
        }
        std::atomic<std::size_t> culledCount{0};
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t chunk) {
            std::size_t chunkCulled = 0;
            found[chunk].clear();
            foundTriangle[chunk].clear();
            for (std::size_t t = chunk * kChunk; t < std::min(triangles.size(), (chunk + 1) * kChunk); ++t) {
                if (outsideShaft(t))
                    continue;
                if (culled(t)) {
                    ++chunkCulled;
                    continue;
                }
                // Prepared in place: an Occluder is ~450 bytes, copies of it showed in profiles.
                Occluder& o = found[chunk].emplace_back();
                if (setup.prepare(triangle(t)[0], triangle(t)[1], triangle(t)[2], o))
                    foundTriangle[chunk].push_back(std::uint32_t(t));
                else
                    found[chunk].pop_back();
            }
            culledCount += chunkCulled;
        });
        occluders.clear();
        triangleOf.clear();
        for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
            for (const Occluder& o : found[chunk])
                occluders.push_back(&o);
            triangleOf.insert(triangleOf.end(), foundTriangle[chunk].begin(), foundTriangle[chunk].end());
        }
        small.assign(occluders.size(), 0);
        stats.culledFrontFaces = culledCount;
        stats.trianglesInShaft = occluders.size();
    }

    /// Hybrid: the small triangles leave the bitmask pass for the ray pass. Returns their
    /// triangle indices.
    std::vector<std::uint32_t> takeSmall(CpuStrategy strategy)
    {
        std::vector<std::uint32_t> smallTriangles;
        if (strategy != CpuStrategy::Bitmask)
            for (std::size_t i = 0; i < occluders.size(); ++i)
                if (occluders[i]->cells < options.smallCells)
                    smallTriangles.push_back(std::uint32_t(i));
        // With the SIMD kernel, the plain bitmask beats the hybrid's ray pass (demo, 1024 sources:
        // 26 against 45 ms), so Auto sends small triangles to ray casting only without it.
        const bool hybrid = strategy == CpuStrategy::Hybrid ||
                            (strategy == CpuStrategy::Auto && !setup.floatKernel &&
                             smallTriangles.size() >= kHybridMinSmallTriangles);
        if (!hybrid)
            smallTriangles.clear();
        for (std::uint32_t& i : smallTriangles) {
            small[i] = 1;
            i = triangleOf[i];
        }
        stats.strategy = hybrid ? "hybrid" : "bitmask";
        stats.smallTriangles = smallTriangles.size();
        return smallTriangles;
    }

    int tilesA() const { return (receiver.na + kTile - 1) / kTile; }
    std::size_t tileCount() const { return std::size_t(tilesA()) * std::size_t((receiver.nb + kTile - 1) / kTile); }

    /// Occluders per tile of receiver samples, largest first: they block the most, and what
    /// they block narrows the shaft for the small ones that follow. One global sort, then
    /// binning in that order, keeps every bin sorted. Bins hold positions in
    /// work.tileOccluders, which follows that order.
    const std::vector<std::vector<std::uint32_t>>& bin()
    {
        std::vector<std::uint32_t>& order = work.order;
        order.clear();
        for (std::size_t i = 0; i < occluders.size(); ++i)
            if (!small[i])
                order.push_back(std::uint32_t(i));
        std::stable_sort(order.begin(), order.end(),
                         [&](std::uint32_t x, std::uint32_t y) { return occluders[x]->cells > occluders[y]->cells; });
        const int tilesB = (receiver.nb + kTile - 1) / kTile;
        std::vector<std::vector<std::uint32_t>>& bins = work.bins;
        bins.resize(std::size_t(tilesA()) * std::size_t(tilesB));
        for (auto& tileBin : bins)
            tileBin.clear();
        std::vector<TileOccluder>& tileOccluders = work.tileOccluders;
        tileOccluders.resize(order.size());
        for (std::size_t n = 0; n < order.size(); ++n) {
            const Occluder& o = *occluders[order[n]];
            const std::uint32_t instance = triangles.instanceOf[triangleOf[order[n]]];
            const bool closed = !closedInstance.empty() && closedInstance[instance];
            tileOccluders[n] = {setup.floatKernel ? setup.singlePrecision(o, closed) : detail::FloatPolygon{},
                                std::int16_t(o.a0), std::int16_t(o.a1), std::int16_t(o.b0), std::int16_t(o.b1),
                                o.path, closed, o.maxD, &o};
            for (int tb = o.b0 / kTile; tb <= o.b1 / kTile; ++tb)
                for (int ta = o.a0 / kTile; ta <= o.a1 / kTile; ++ta)
                    bins[std::size_t(tb) * std::size_t(tilesA()) + std::size_t(ta)].push_back(std::uint32_t(n));
        }
        return bins;
    }

    /// The receiver samples of one tile as groups of eight lanes for the SIMD kernel: lane
    /// (b - b0) * kTile + (a - a0) is sample (a, b), and group g holds lanes 8 g to 8 g + 7, so
    /// kRowsPerGroup whole rows of the tile.
    static constexpr int kTileLanes = kTile * kTile;
    static constexpr int kRowsPerGroup = detail::kLanes / kTile;
    static constexpr int kGroups = kTileLanes / detail::kLanes;
    static_assert(detail::kLanes % kTile == 0 && kTileLanes <= 64, "groups of whole tile rows; lane masks in 64 bits");
    struct TileLanes {
        detail::LaneGroup group[kGroups];
        std::uint64_t inside = 0;   // per lane: inside the grid
        /// The kernel's row for lanes outside the grid: it only ever ORs zeros into it.
        std::array<std::uint64_t, kMaxSourceSamples / 64> scratch{};
    };

    /// Fills `lanes` in place: the scratch row's address must stay valid.
    void tileLanes(int a0, int b0, TileLanes& lanes) const
    {
        lanes.inside = 0;
        for (int lane = 0; lane < kTileLanes; ++lane) {
            const int a = a0 + lane % kTile, b = b0 + lane / kTile;
            const bool inside = a < receiver.na && b < receiver.nb;
            // Lanes outside the grid compute with the tile's first sample and are never active:
            // the kernel only ORs zeros into their scratch row.
            const int j = inside ? b * receiver.na + a : b0 * receiver.na + a0;
            detail::LaneGroup& g = lanes.group[lane / 8];
            g.s[lane % 8] = setup.receiverS[std::size_t(j)];
            g.t[lane % 8] = setup.receiverT[std::size_t(j)];
            g.d[lane % 8] = setup.receiverD[std::size_t(j)];
            const glm::dvec3& r = setup.receiverInSource[std::size_t(j)];
            g.sLo[lane % 8] = float(r.x - double(g.s[lane % 8]));
            g.tLo[lane % 8] = float(r.y - double(g.t[lane % 8]));
            g.dLo[lane % 8] = float(r.z - double(g.d[lane % 8]));
            if (lane % 8 == 0)
                g.sReach = g.tReach = 0.0f;
            g.sReach = std::max(g.sReach, std::abs(g.s[lane % 8]));
            g.tReach = std::max(g.tReach, std::abs(g.t[lane % 8]));
            g.shiftS[lane % 8] = float(setup.jitterShift[std::size_t(j)].x);
            g.shiftT[lane % 8] = float(setup.jitterShift[std::size_t(j)].y);
            g.shifted = setup.jittered;
            g.rowCentres = setup.rowCentres.data();
            g.metresPerS = float(setup.metresPerS);
            g.metresPerT = float(setup.metresPerT);
            g.bandBudget = float(kFloatBandBudget);
            g.rows[lane % 8] = inside ? map.row(j).data() : lanes.scratch.data();
            lanes.inside |= std::uint64_t(inside) << lane;
        }
    }

    /// The receiver samples of a tile (bit indices).
    void tileSamples(std::uint32_t tile, std::vector<int>& out) const
    {
        const int a0 = int(tile % std::uint32_t(tilesA())) * kTile, b0 = int(tile / std::uint32_t(tilesA())) * kTile;
        for (int b = b0; b < std::min(receiver.nb, b0 + kTile); ++b)
            for (int a = a0; a < std::min(receiver.na, a0 + kTile); ++a)
                out.push_back(b * receiver.na + a);
    }

    /// Whether `o`, on `path`, may hide a source sample in `open` from a receiver sample of
    /// [a0, a1] x [b0, b1] (Setup::mayHit). The samples whose backprojections bound the set's: on
    /// a flat receiver the rectangle's corners, on a bumpy one every sample (its rectangles are
    /// not planar).
    bool mayHitFrom(const TileOccluder& o, Path path, int a0, int a1, int b0, int b1, const SourceBox& open) const
    {
        const int na = receiver.na;
        if (!setup.bumpy) {
            const std::array<int, 4> corners = {b0 * na + a0, b0 * na + a1, b1 * na + a0, b1 * na + a1};
            if (path == Path::Float)
                return setup.mayHitFloat(o.single, corners, open);
            return setup.mayHit(*o.occluder, path, corners.data(), 4, open);
        }
        std::array<int, kTile * kTile> samples;
        int count = 0;
        for (int b = b0; b <= b1; ++b)
            for (int a = a0; a <= a1; ++a)
                samples[std::size_t(count++)] = b * na + a;
        return setup.mayHit(*o.occluder, path, samples.data(), count, open);
    }

    /// The bitmask pass (§2-5): tiles in parallel, each owning its receiver samples' rows. `only`:
    /// these tiles (indices into `bins`) instead of all.
    void bitmaskPass(const std::vector<std::vector<std::uint32_t>>& bins, bool narrow,
                     const std::vector<std::uint32_t>* only = nullptr)
    {
        std::atomic<std::uint64_t> narrowedAway{0}, pairs{0}, floatPairs{0}, floatFallbacks{0};
        const int words = map.wordsPerRow();
        // Lanes whose rows are full are switched off; rechecked every this many float occluders.
        constexpr int kFullRefresh = 32;
        constexpr std::size_t kPrefetch = 4;
        const std::size_t tileCount = only ? only->size() : bins.size();
        const std::vector<TileOccluder>& tileOccluders = work.tileOccluders;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tileCount, 1), [&](const auto& range) {
            std::uint64_t tilePairs = 0, tileFloatPairs = 0, tileSkipped = 0, tileFallbacks = 0;
            for (std::size_t k = range.begin(); k != range.end(); ++k) {
                const std::size_t tile = only ? (*only)[k] : k;
                const int ta = int(tile % std::size_t(tilesA())), tb = int(tile / std::size_t(tilesA()));
                const int a0 = ta * kTile, b0 = tb * kTile;
                const int aEnd = std::min(receiver.na, a0 + kTile), bEnd = std::min(receiver.nb, b0 + kTile);
                TileLanes lanes;
                if (setup.floatKernel)
                    tileLanes(a0, b0, lanes);
                // The source samples the tile still sees. Kept per lane group instead (measured with
                // 4x4 tiles and groups of 2x4), the sets rejected 15% more pairs on the 128x128
                // wall but cost more than they saved.
                SourceBox open;
                int sinceNarrowed = -1;   // -1: not narrowed yet
                std::uint64_t full = 0;   // per lane: row already full
                int sinceFullChecked = kFullRefresh;
                const std::vector<std::uint32_t>& tileBin = bins[tile];
                for (std::size_t next = 0; next < tileBin.size(); ++next) {
                    if (next + kPrefetch < tileBin.size()) {
                        const char* ahead = reinterpret_cast<const char*>(&tileOccluders[tileBin[next + kPrefetch]]);
                        for (std::size_t line = 0; line < sizeof(TileOccluder); line += 64)
                            __builtin_prefetch(ahead + line);
                    }
                    const TileOccluder& o = tileOccluders[tileBin[next]];
                    // This tile's part of the occluder's region, and the cheapest path there.
                    const int ia0 = std::max<int>(a0, o.a0), ia1 = std::min<int>(aEnd - 1, o.a1);
                    const int ib0 = std::max<int>(b0, o.b0), ib1 = std::min<int>(bEnd - 1, o.b1);
                    const Path path = o.path == Path::Float || setup.bumpy
                                          ? o.path
                                          : setup.pathFor(o.maxD, setup.nearestSample(ia0, ia1, ib0, ib1));
                    if (narrow) {
                        if (sinceNarrowed < 0 || sinceNarrowed >= kNarrowRefresh) {
                            open = setup.unblockedBox(map, a0, aEnd - 1, b0, bEnd - 1);
                            sinceNarrowed = 0;
                            if (open.empty())
                                break;   // the whole tile is blocked
                        }
                        ++sinceNarrowed;
                        if (!mayHitFrom(o, path, ia0, ia1, ib0, ib1, open)) {
                            ++tileSkipped;
                            continue;
                        }
                    }
                    if (path == Path::Float && ++sinceFullChecked >= kFullRefresh) {
                        full = 0;
                        for (int lane = 0; lane < kTileLanes; ++lane)
                            if ((lanes.inside >> lane & 1) && rowFull(lanes.group[lane / 8].rows[lane % 8], words, setup.S))
                                full |= std::uint64_t(1) << lane;
                        sinceFullChecked = 0;
                    }
                    // The kernel's groups of kRowsPerGroup rows.
                    const unsigned columns = ((2u << (ia1 - a0)) - 1u) & ~((1u << (ia0 - a0)) - 1u);
                    for (int g = (ib0 - b0) / kRowsPerGroup; g <= (ib1 - b0) / kRowsPerGroup; ++g) {
                        const int gr0 = b0 + kRowsPerGroup * g;
                        const int gb0 = std::max(ib0, gr0), gb1 = std::min(ib1, gr0 + kRowsPerGroup - 1);
                        // A sloping receiver's group may be well clear of an occluder that reaches
                        // the tile's nearest sample (furniture on a floor).
                        const Path groupPath = path == Path::Float || setup.bumpy
                                                   ? path
                                                   : setup.pathFor(o.maxD, setup.nearestSample(ia0, ia1, gb0, gb1));
                        if (groupPath == Path::Float) {
                            // Lanes: columns ia0..ia1 of rows gb0..gb1, inside the grid, not full.
                            unsigned active = 0;
                            for (int b = gb0; b <= gb1; ++b)
                                active |= columns << (kTile * (b - gr0));
                            active &= unsigned(~full >> (8 * g) & lanes.inside >> (8 * g));
                            unsigned fallback = 0;
                            const int n = detail::backprojectRowsAvx2(o.single, lanes.group[g], active, setup.na,
                                                                      setup.nb, &fallback);
                            tilePairs += std::uint64_t(n);
                            tileFloatPairs += std::uint64_t(n);
                            // What the kernel could not prove, in double.
                            for (; fallback; fallback &= fallback - 1) {
                                const int lane = std::countr_zero(fallback);
                                const int j = (gr0 + lane / kTile) * receiver.na + a0 + lane % kTile;
                                setup.backproject(*o.occluder, Path::Double, j, map.row(j).data());
                                ++tilePairs;
                                ++tileFallbacks;
                            }
                            continue;
                        }
                        // A receiver row parallel to the source plane (a floor seen from a wall) lies
                        // at one distance: one clip serves all its samples. The distance is affine
                        // along the row, so its two ends tell.
                        static_assert(kRowsPerGroup == 1, "a lane group is part of one receiver row");
                        const int j0 = gb0 * receiver.na + ia0, j1 = gb1 * receiver.na + ia1;
                        const double z0 = setup.receiverInSource[std::size_t(j0)].z;
                        const bool sharedClip = groupPath == Path::Clip && !setup.bumpy &&
                                                o.maxD >= Setup::clipDistance(z0) &&
                                                std::abs(setup.receiverInSource[std::size_t(j1)].z - z0) <= 1e-12 * z0;
                        const auto eachOpenRow = [&](const auto& backproject) {
                            for (int b = gb0; b <= gb1; ++b)
                                for (int a = ia0; a <= ia1; ++a) {
                                    const int j = b * receiver.na + a;
                                    std::uint64_t* row = map.row(j).data();
                                    if (rowFull(row, words, setup.S))
                                        continue;
                                    backproject(j, row);
                                    ++tilePairs;
                                }
                        };
                        if (sharedClip) {
                            const ClippedPolygon clipped = Setup::clippedFor(*o.occluder, z0);
                            if (clipped.count >= 3)
                                eachOpenRow([&](int j, std::uint64_t* row) {
                                    setup.backprojectPolygon(clipped.vertices.data(), clipped.count,
                                                             setup.receiverInSource[std::size_t(j)],
                                                             setup.jitterShift[std::size_t(j)], row, nullptr);
                                });
                        } else {
                            eachOpenRow([&](int j, std::uint64_t* row) { setup.backproject(*o.occluder, groupPath, j, row); });
                        }
                    }
                }
            }
            pairs += tilePairs;
            floatPairs += tileFloatPairs;
            narrowedAway += tileSkipped;
            floatFallbacks += tileFallbacks;
        });
        stats.pairs += pairs;
        stats.floatPairs += floatPairs;
        stats.narrowedAway += narrowedAway;
        stats.floatFallbacks += floatFallbacks;
    }

    /// Hybrid: the still-unblocked rays against a BVH of the small triangles only.
    void rayPass(const std::vector<std::uint32_t>& smallTriangles)
    {
        WorldTriangles subset;
        subset.vertices.reserve(3 * smallTriangles.size());
        for (std::uint32_t t : smallTriangles) {
            subset.vertices.insert(subset.vertices.end(), triangle(t), triangle(t) + 3);
            subset.instanceOf.push_back(triangles.instanceOf[t]);
        }
        const RayCastScene rays(subset, /*fastBuild=*/true);
        stats.raysCast = rays.sampleUnblocked(source, receiver, map, {.jitter = options.jitter, .heights = options.heights});
    }
};

} // namespace

CpuBitmaskSampler::CpuBitmaskSampler(const Scene& scene) : triangles_(worldTriangles(scene))
{
    for (const Instance& instance : scene.instances)
        instances_.push_back({scene.meshes[instance.mesh].watertight, scene.instanceBounds(instance)});
}
CpuBitmaskSampler::CpuBitmaskSampler(WorldTriangles triangles) : triangles_(std::move(triangles)) {}

void CpuBitmaskSampler::setScene(const Scene& scene)
{
    triangles_ = worldTriangles(scene);
    instances_.clear();
    for (const Instance& instance : scene.instances)
        instances_.push_back({scene.meshes[instance.mesh].watertight, scene.instanceBounds(instance)});
    {
        std::lock_guard lock(rayCasterMutex_);
        rayCaster_.reset();   // built again, for the new triangles, when RayCast is next chosen
    }
    std::lock_guard lock(probeMutex_);
    probeMemo_ = {};
}

std::vector<char> CpuBitmaskSampler::cullableInstances(const Patch& receiver, const Bounds* displacedBox) const
{
    std::vector<char> cullable(instances_.size(), 0);
    for (std::size_t i = 0; i < instances_.size(); ++i) {
        if (!instances_[i].watertight)
            continue;
        if (!displacedBox) {
            cullable[i] = receiverApartFrom(instances_[i].bounds, receiver);
            continue;
        }
        // A bumpy receiver: no displaced sample may lie inside the mesh. receiverApartFrom's
        // test, on the box of the displaced samples.
        const Bounds& r = *displacedBox;
        const Bounds& b = instances_[i].bounds;
        const float pad = 1e-4f * (1.0f + glm::length(r.max - r.min));
        cullable[i] = glm::any(glm::lessThan(b.max + pad, r.min)) || glm::any(glm::greaterThan(b.min - pad, r.max));
    }
    return cullable;
}

CpuBitmaskSampler::~CpuBitmaskSampler() = default;

bool CpuBitmaskSampler::simdAvailable() { return detail::floatRowsAvailable(); }

std::unique_ptr<CpuBitmaskSampler::Workspace> CpuBitmaskSampler::takeWorkspace() const
{
    std::lock_guard lock(workspaceMutex_);
    if (idleWorkspaces_.empty())
        return std::make_unique<Workspace>();
    std::unique_ptr<Workspace> work = std::move(idleWorkspaces_.back());
    idleWorkspaces_.pop_back();
    return work;
}

void CpuBitmaskSampler::returnWorkspace(std::unique_ptr<Workspace> work) const
{
    constexpr std::size_t kMaxIdle = 4;   // callers sampling concurrently
    std::lock_guard lock(workspaceMutex_);
    if (idleWorkspaces_.size() < kMaxIdle)
        idleWorkspaces_.push_back(std::move(work));
}

std::shared_ptr<const RayCastScene> CpuBitmaskSampler::wholeSceneCaster() const
{
    std::lock_guard lock(rayCasterMutex_);
    if (!rayCaster_)
        rayCaster_ = std::make_shared<const RayCastScene>(triangles_);
    return rayCaster_;
}

HiddenSampleMap CpuBitmaskSampler::sample(const Patch& source, const Patch& receiver, const BitmaskOptions& options,
                                          BitmaskStats* stats) const
{
    validatePatchPair(source, receiver);
    if (options.heights)
        validateReceiverHeights(source, receiver, *options.heights);
    // A bumpy receiver (§8). All-zero heights move no sample: the flat path, unchanged.
    const bool bumpy = !flatReceiver(options.heights);
    std::vector<glm::dvec3> displaced;
    Bounds displacedBox;
    glm::dvec3 normal(0.0);
    double lowest = 0.0, highest = 0.0;
    if (bumpy) {
        // The same expression as RayCastScene's and displacedReceiverSample's: the same bits.
        normal = receiverNormalTowardSource(source, receiver);
        const std::vector<double>& metres = options.heights->metres;
        displaced.resize(metres.size());
        for (int j = 0; j < receiver.sampleCount(); ++j) {
            displaced[std::size_t(j)] = receiver.sample(j) + metres[std::size_t(j)] * normal;
            displacedBox.extend(glm::vec3(displaced[std::size_t(j)]));
        }
        const auto [lo, hi] = std::minmax_element(metres.begin(), metres.end());
        lowest = *lo, highest = *hi;
    }
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    BitmaskStats local;
    const auto setupStart = Clock::now();

    std::shared_ptr<const HoughMaskTable> table;
    if (options.mode == MaskMode::Table) {
        const auto tableStart = Clock::now();
        std::lock_guard lock(tableMutex_);
        if (!table_ || table_->width() != options.tableWidth || table_->height() != options.tableHeight ||
            table_->grid() != std::pair(source.na, source.nb)) {
            table_ = std::make_shared<const HoughMaskTable>(source.na, source.nb, options.tableWidth, options.tableHeight);
            local.tableMs = msSince(tableStart);
        }
        table = table_;
    }
    // Table mode is the paper's method as published: every triangle by bitmask, no narrowing.
    const bool exact = options.mode == MaskMode::Exact;
    const bool narrow = options.narrowShaft && exact;
    const CpuStrategy strategy = exact ? options.strategy : CpuStrategy::Bitmask;

    std::unique_ptr<Workspace> work = takeWorkspace();
    auto body = [&] {
        Setup setup(source, receiver, options.jitter, bumpy ? &displaced : nullptr);
        setup.table = table.get();
        setup.floatKernel = exact && options.simd && source.na <= 32 && detail::floatRowsAvailable();
        Pass pass{setup, triangles_, source, receiver, options, map, local, *work};

        // A bumpy receiver's segments end in the prism of the receiver between its lowest and
        // highest bump (§8), so its shaft is the hull of the source's corners and that prism.
        const ShaftHull hull = bumpy ? ShaftHull([&] {
            std::vector<glm::dvec3> points;
            for (int k = 0; k < 4; ++k) {
                const glm::dvec3 rc = receiver.corner + double(k & 1) * receiver.u + double(k >> 1) * receiver.v;
                points.push_back(source.corner + double(k & 1) * source.u + double(k >> 1) * source.v);
                points.push_back(rc + lowest * normal);
                points.push_back(rc + highest * normal);
            }
            return points;
        }())
                                     : ShaftHull(source, receiver);
        std::vector<char> instanceOutside(instances_.size());
        for (std::size_t i = 0; i < instances_.size(); ++i)
            instanceOutside[i] = hull.excludesBox(instances_[i].bounds.min, instances_[i].bounds.max);
        pass.closedInstance.resize(instances_.size());
        for (std::size_t i = 0; i < instances_.size(); ++i)
            pass.closedInstance[i] = instances_[i].watertight;
        pass.init(options.watertightCulling ? cullableInstances(receiver, bumpy ? &displacedBox : nullptr)
                                            : std::vector<char>{},
                  std::move(instanceOutside), hull);
        // Few source samples: ray casting everything may be cheaper than the bitmask, whose cost
        // follows (triangle, receiver sample) pairs, not rays. The pair estimate ignores the
        // narrowed shaft, which removes 40-80% of the pairs at fewer source samples and denser
        // receivers; where it is not clear-cut, both methods are measured on a few tiles first.
        const bool estimateSaysRays =
            strategy == CpuStrategy::Auto && pass.rayCastingIsCheaper(&local.estimatedPairs);
        const double estimatePerRay = double(local.estimatedPairs) / double(map.rayCount());
        bool probe = estimateSaysRays && estimatePerRay < kProbePairsPerRay && setup.floatKernel && !bumpy &&
                     receiver.sampleCount() >= kProbeMinSamples &&
                     local.estimatedPairs / std::uint64_t(kTile * kTile) <= kProbeMaxBinEntries;
        const std::array<int, 4> grids = {source.na, source.nb, receiver.na, receiver.nb};
        bool rememberedRays = false;
        if (probe) {
            std::lock_guard lock(probeMutex_);
            if (probeMemo_.grids == grids && probeMemo_.callsLeft > 0) {
                --probeMemo_.callsLeft;
                probe = false;
                local.reusedProbe = true;
                rememberedRays = probeMemo_.rays;
            }
        }
        if (strategy == CpuStrategy::RayCast || (estimateSaysRays && !probe && !local.reusedProbe) || rememberedRays) {
            local.strategy = "raycast";
            const std::shared_ptr<const RayCastScene> caster = wholeSceneCaster();
            local.setupMs = msSince(setupStart);
            const auto rayStart = Clock::now();
            local.raysCast =
                caster->sampleUnblocked(source, receiver, map, {.jitter = options.jitter, .heights = options.heights});
            local.rayMs = msSince(rayStart);
            return;
        }
        pass.prepareAll();
        const std::vector<std::uint32_t> small = pass.takeSmall(strategy);
        const auto& bins = pass.bin();
        local.setupMs = msSince(setupStart);

        const auto sampleStart = Clock::now();
        if (probe && small.empty()) {
            // One tile in kProbeStride by bitmask and another by rays, a batch of each at a time,
            // timed; their rows are final either way. Probing stops once one method costs twice
            // the other per tile (or the probe tiles run out). The tiles are drawn at random over
            // the whole receiver: in row order the first batches would all lie along one edge (a
            // floor's edge by the wall costs nothing either way), and every 8th tile of a grid 16
            // tiles wide is two columns of it. A fixed seed: the same tiles every call.
            std::vector<std::uint32_t> shuffled(bins.size());
            std::iota(shuffled.begin(), shuffled.end(), 0u);
            std::mt19937 scramble(12345);
            std::shuffle(shuffled.begin(), shuffled.end(), scramble);
            const std::size_t probeTiles = shuffled.size() / kProbeStride;
            std::vector<std::uint32_t> bitmaskTiles(shuffled.begin(), shuffled.begin() + std::ptrdiff_t(probeTiles));
            std::vector<std::uint32_t> rayTiles(shuffled.begin() + std::ptrdiff_t(probeTiles),
                                                shuffled.begin() + std::ptrdiff_t(2 * probeTiles));
            std::vector<std::uint32_t> rest(shuffled.begin() + std::ptrdiff_t(2 * probeTiles), shuffled.end());
            const std::shared_ptr<const RayCastScene> caster = wholeSceneCaster();
            std::vector<int> samples;
            RayCastOptions rayOptions{.jitter = options.jitter, .receiverSubset = &samples};
            const std::size_t batch = std::max<std::size_t>(4, 2 * std::size_t(tbb::this_task_arena::max_concurrency()));
            std::size_t bitmaskDone = 0, rayDone = 0;
            double bitmaskMs = 0.0, rayMs = 0.0;
            while (bitmaskDone < bitmaskTiles.size() || rayDone < rayTiles.size()) {
                if (bitmaskDone < bitmaskTiles.size()) {
                    const std::size_t end = std::min(bitmaskDone + batch, bitmaskTiles.size());
                    const std::vector<std::uint32_t> part(bitmaskTiles.begin() + std::ptrdiff_t(bitmaskDone),
                                                          bitmaskTiles.begin() + std::ptrdiff_t(end));
                    const auto start = Clock::now();
                    pass.bitmaskPass(bins, narrow, &part);
                    bitmaskMs += msSince(start);
                    bitmaskDone = end;
                }
                if (rayDone < rayTiles.size()) {
                    const std::size_t end = std::min(rayDone + batch, rayTiles.size());
                    samples.clear();
                    for (std::size_t k = rayDone; k < end; ++k)
                        pass.tileSamples(rayTiles[k], samples);
                    const auto start = Clock::now();
                    local.raysCast += caster->sampleUnblocked(source, receiver, map, rayOptions);
                    rayMs += msSince(start);
                    rayDone = end;
                }
                // Stop once one method costs twice the other per tile, or the probe has cost a
                // tenth of what the faster would take for the whole receiver.
                const double perBitmask = bitmaskMs / double(bitmaskDone), perRay = rayMs / double(rayDone);
                const double wholeFaster = std::min(perBitmask, perRay) * double(bins.size());
                if (bitmaskDone >= 2 * batch &&
                    (perBitmask > 2.0 * perRay || perRay > 2.0 * perBitmask || bitmaskMs + rayMs > 0.1 * wholeFaster))
                    break;
            }
            local.rayMs += rayMs;
            rest.insert(rest.end(), bitmaskTiles.begin() + std::ptrdiff_t(bitmaskDone), bitmaskTiles.end());
            rest.insert(rest.end(), rayTiles.begin() + std::ptrdiff_t(rayDone), rayTiles.end());
            local.probed = true;
            const bool rays = bitmaskMs / double(bitmaskDone) > rayMs / double(rayDone);
            {
                std::lock_guard lock(probeMutex_);
                probeMemo_ = {grids, rays, kProbeReuse};
            }
            if (!rays) {
                local.strategy = "bitmask";
                pass.bitmaskPass(bins, narrow, &rest);
            } else {
                local.strategy = "raycast";
                samples.clear();
                for (std::uint32_t t : rest)
                    pass.tileSamples(t, samples);
                const auto restStart = Clock::now();
                local.raysCast += caster->sampleUnblocked(source, receiver, map, rayOptions);
                local.rayMs += msSince(restStart);
            }
            local.sampleMs = msSince(sampleStart) - local.rayMs;
            return;
        }
        pass.bitmaskPass(bins, narrow);
        local.sampleMs = msSince(sampleStart);
        if (!small.empty()) {
            const auto rayStart = Clock::now();
            pass.rayPass(small);
            local.rayMs = msSince(rayStart);
        }
    };
    if (options.threads > 0) {
        tbb::task_arena arena(options.threads);
        arena.execute(body);
    } else {
        body();
    }
    returnWorkspace(std::move(work));
    if (stats)
        *stats = local;
    return map;
}

} // namespace sightline
