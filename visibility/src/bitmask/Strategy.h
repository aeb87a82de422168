#pragma once
// Internal to the CPU bitmask sampler: how Auto chooses between the bitmask and ray casting.
//
// The bitmask's cost follows (occluder, receiver sample) pairs after the narrowed shaft, ray
// casting's follows the rays; neither is known before sampling. Auto estimates the pairs from a
// sample of the triangles, decides where the estimate is clear-cut, and otherwise measures both
// methods on a few random tiles (their rows are final either way) and finishes with the faster.
// A choice, estimated or measured, serves later calls on a similar configuration (the editor and
// animations sample slowly changing ones). The decisions are plain functions of measured and
// estimated costs, tested on their own (tst_Strategy).

#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "visibility/Patch.h"

namespace sightline::bitmask {

/// What Auto knows before it samples, estimated from every 32nd triangle the shaft keeps.
struct CostEstimate {
    std::uint64_t rays = 0;
    std::uint64_t estimatedPairs = 0;       ///< (triangle, receiver sample) pairs, before narrowing
    std::uint64_t estimatedTriangles = 0;   ///< triangles in the shaft, not culled
    bool floatKernel = false;               ///< the SIMD kernel takes well-conditioned occluders
    bool bumpy = false;
    int receiverSamples = 0;
    /// The finer of the two grids (0: the receiver's): ray casting starts its packets at the
    /// other end (raycast/ProvenRayCaster.h), whichever patch is the source.
    int finerSamples = 0;
    /// The patches swapped roles (swapPatchRoles): the estimate is of the swapped call.
    bool swappedRoles = false;
    /// The share of the rays still open when the strategy starts (the inner proxies answered
    /// the rest): ray casting skips answered rays, the bitmask does not.
    double openShare = 1.0;
};

/// What a unit of each method's work costs, fitted to bench runs (README, "Auto's cost model"):
/// - the bitmask (fitted over the demo, its floor, the dense mesh, few occluders and the twelve
///   bench scenes at 64-1024 sources and 32-128 receiver samples): setup per triangle in the
///   shaft, and its pass per estimated pair, which falls as the pairs per ray grow (the narrowed
///   shaft skips more of them once a tile is blocked): passNsPerPair * (pairs per ray / 4)^-passFalloff;
/// - ray casting (raycast/ProvenRayCaster.h, fitted over all 27 bench scenes at 32-1024 sources
///   and 32-64 receiver samples, processor time of one thread scaled to the bitmask's units): per
///   ray, exp(rayLogBase + rayLogTriangles ln(1 + triangles in the shaft) + rayLogPairs l +
///   rayLogPairs2 l^2 + rayLogSide ln(receiver side) + rayCoverage c), l = ln(1 + pairs per ray)
///   (clamped to [0, 7], the fitted range), c = pairs / (triangles x receiver samples), the part
///   of the receiver an average triangle's region covers. A deeper tree costs each ray more;
///   pairs crowding a ray first cost more (rays pass near more triangles) and then less (rays stop
///   at their first proven hit, and few are left to the reference); a finer receiver grid makes
///   packets more coherent; pairs that come from a few large triangles (walls of an architectural
///   interior, c near 1) cost rays far less than as many from clutter.
struct CostModel {
    double setupNsPerTriangle = 0.0;
    double passNsPerPair = 0.0;
    double passFalloff = 0.0;
    double rayLogBase = 0.0;
    double rayLogTriangles = 0.0;
    double rayLogPairs = 0.0;
    double rayLogPairs2 = 0.0;
    double rayLogSide = 0.0;
    double rayCoverage = 0.0;

    /// The bitmask pass's cost per pair for this many pairs per ray.
    double passNs(double pairsPerRay) const;
    /// Ray casting's cost per ray with this many triangles in the shaft and pairs per ray, for a
    /// receiver grid of `receiverSamples`, where an average triangle's region covers `coverage`
    /// of the receiver (0-1).
    double rayNs(std::uint64_t trianglesInShaft, double pairsPerRay, int receiverSamples, double coverage = 0.0) const;
};

/// The model Auto uses: with the SIMD kernel, and without it (the double kernel's pairs cost more).
const CostModel& measuredCosts(bool floatKernel);

/// Predicted milliseconds of each method for an estimate.
double predictedBitmaskMs(const CostEstimate& estimate, const CostModel& model);
double predictedRayMs(const CostEstimate& estimate, const CostModel& model);

enum class Plan {
    Bitmask,   ///< the bitmask is clearly cheaper, or nothing better can be known cheaply
    RayCast,   ///< ray casting is clearly cheaper
    Probe,     ///< not clear-cut: time both on a few tiles first
};

/// The estimate's verdict: clear-cut when one prediction is under half the other (the predictions
/// miss the narrowed shaft and the scene's ray cost by up to that much over the bench scenes);
/// otherwise probe, where the receiver has tiles enough for a probe (and its bins are not
/// huge), else the cheaper prediction. With the roles swapped: kSwappedRaysClearCut (below).
Plan planFor(const CostEstimate& estimate, const CostModel& model);

/// With the patches' roles swapped the receiver has at most 1023 samples, too few tiles to time
/// the bitmask on, and the ray model's inputs (the swapped call's pairs per ray, a coarse
/// receiver) lie outside the range it was fitted on: against one thread's times it predicts
/// rays 2.2-8 times too cheap (cluttered rooms worst) (docs/benchmarks.md, "Swapped roles"). So
/// the plan is the bitmask where its prediction is no more than the rays' (interiors, halls,
/// cluttered rooms at 128 source samples: the rays would only be dearer still), rays where it is
/// over kSwappedRaysClearCut times (dense meshes at 32 source samples), and in between the rays
/// of a few receiver samples are timed (swappedRaysOrTimeBitmask).
inline constexpr double kSwappedBitmaskClearCut = 1.0;
inline constexpr double kSwappedRaysClearCut = 8.0;

/// The swapped probe's receiver samples (an eighth, at least one, drawn with a fixed seed) in
/// `probe`, and the others in `rest`, both in increasing order.
void swappedProbeSamples(int receiverSamples, std::vector<int>& probe, std::vector<int>& rest);

/// The swapped probe's first verdict, from the rays timed on a few receiver samples and scaled
/// to the whole call (`raysWholeMs`, swappedRaysWholeMs): rays where that is under
/// kSwappedRaysUntimedBelow times the bitmask's prediction; otherwise the bitmask is timed too, on this call's whole
/// answer (swappedMeasuredChoosesRays). Of the 100 swapped calls of seeds 1-12 at 32 and 128
/// source samples against 32x32 (docs/benchmarks.md, "The swapped probe times the bitmask"), 18
/// fall between the clear-cut rules: there a whole bitmask call took 0.79-1.52 times its
/// prediction on one thread; where the bitmask was the better strategy the probe's rays came to
/// 1.74-3.68 times it, and where rays were, 0.28-0.45 times it but for dense-mesh-8 at 128
/// sources (1.07-1.27); tiles of 64x64 receivers where rays were better, 0.49-0.91. Rays under
/// the prediction are so taken without timing the bitmask: were the bitmask as cheap as 0.79 of
/// its prediction, the rays' probe runs high (below), so the loss would be a few percent. A
/// fixed weight alone (the rays against twice the prediction) was nearly twice as slow on an
/// unseen cluttered room once the bitmask cost about its prediction.
inline constexpr double kSwappedRaysUntimedBelow = 1.0;
enum class SwappedVerdict { Rays, TimeBitmask };
SwappedVerdict swappedRaysOrTimeBitmask(double bitmaskPredictedMs, double raysWholeMs);
/// The rays' whole call, one thread, from the probe's part (`probeMs` for `probed` of `samples`).
double swappedRaysWholeMs(double probeMs, std::size_t probed, std::size_t samples);

/// After a swapped probe that timed the bitmask's whole call (its setup and pass, one thread):
/// whether later calls go by rays. This call's answer is the bitmask's, already paid. The probe's
/// rays, scaled from an eighth of the samples, ran 0.98-1.9 times a whole call's by rays: true on
/// most dense meshes, 1.16-1.40 on cluttered-rooms-12 at 32 x 32², 1.6-1.9 on dense-mesh-8 at 128
/// x 32² (per-call costs counted eight times, and a probe too small for the ray caster to choose
/// its traversal: raycast/ProvenRayCaster.h), and high in a cold call. So the bitmask is kept only
/// where it beats the probe's rays by more than kProbeRaysOverestimate: where they run true, rays
/// then lose at most 10%, Auto's bar.
inline constexpr double kProbeRaysOverestimate = 1.10;
bool swappedMeasuredChoosesRays(double raysWholeMs, double bitmaskSetupMs, double bitmaskPassMs);

/// How many later calls a rays verdict of a swapped probe that timed the bitmask serves. That
/// probe paid a whole bitmask call where rays would have cost less (dense-mesh-8 at 128 x 32²:
/// two to three times as much), so its choice serves enough calls that the bitmask's time adds at
/// most kSwappedProbeShare of theirs by rays: at least kProbeReuse, at most kMaxSwappedReuse.
/// (The probe's scaled rays run high, so the count errs long.)
inline constexpr double kSwappedProbeShare = 0.05;
inline constexpr int kMaxSwappedReuse = 64;
int swappedRaysMemoCalls(double raysWholeMs, double bitmaskWholeMs);

/// One method's part of a probe: one thread's processor time, and the share of the whole
/// receiver's work for that method it covered (probeShare).
struct ProbePart {
    double ms = 0.0;
    double share = 0.0;
    /// The whole receiver by this method, at the probe's rate.
    double wholeMs() const { return share > 0.0 ? ms / share : 0.0; }
};

/// The share of a method's work that its probed tiles hold: the mean of their share of the tiles
/// and of `probedUnits` of `totalUnits`, units being what its cost follows across tiles (the
/// bitmask: bin entries, i.e. occluders over the tile; rays: rays still free when the probe
/// starts). Tiles differ in work far more than a unit does (a statue fills a few of them): by
/// tiles alone the eight of a 64-tile dense mesh misjudged its rays by a third and its bitmask by
/// a sixth, both the wrong way. By units alone another dense mesh's rays came out 1.5 times too
/// dear: per-call and per-tile costs do not follow the units, nor do rays of different kinds (a
/// tile whose rays the inner proxies mostly answered keeps the dear ones, near the surface).
/// (docs/benchmarks.md, "The swapped setup, and Auto's probe by work"). Where no unit was probed
/// the tiles' share stands in.
double probeShare(double probedUnits, double totalUnits, std::size_t probedTiles, std::size_t tiles);

/// While probing: whether enough is known to stop, from each method's part so far, the tiles it
/// has done and the batch size.
bool probeIsDecided(const ProbePart& bitmask, std::size_t bitmaskTiles, const ProbePart& rays, std::size_t rayTiles,
                    std::size_t batch);

/// The probe's verdict: ray casting when a whole call by rays would cost less than a whole call
/// by the bitmask plus its setup (`bitmaskSetupMs`: clipping, regions, binning). The choice serves
/// later calls (ProbeMemo), which by rays skip that setup altogether. The sampler measures all of
/// these as one thread's processor time (the probe's setup and batches run on one thread), which
/// other jobs sharing the machine do not stretch as they stretch the wall time.
bool probeChoosesRays(const ProbePart& bitmask, const ProbePart& rays, double bitmaskSetupMs);

/// The tiles a probe times (each method's, in the order it does them) and those it leaves.
struct ProbeTiles {
    std::vector<std::uint32_t> bitmask, rays, rest;
};

/// Auto's probe tiles on a grid of `tiles` tiles, `tilesA` to a row: `perMethod` pairs of
/// neighbouring tiles (side by side, or one above the other on a grid one tile wide) drawn at
/// random over the receiver (a fixed seed: the same tiles every call), one of each pair to each
/// method, which gets the first alternating. Neighbours see nearly the same occluders, so both
/// methods are timed on like work: tiles drawn independently for each can hand one method the
/// receiver's costliest tiles, and the choice to the slower method.
ProbeTiles probeTiles(std::size_t tiles, std::size_t tilesA, std::size_t perMethod);

/// What a probe decides, for the call that made it and for later ones.
struct ProbeVerdict {
    bool restByRays = false;   ///< this call's untimed tiles: its setup is paid, so the wholes without it
    bool memoRays = false;     ///< later calls on a similar configuration (probeChoosesRays)
    int memoCalls = 0;         ///< how many later calls that choice serves
};

/// The probe's verdict. `warm`: the sampler has sampled these grids before, so the setup's time
/// is what later calls pay. The first call on a pair of grids pays first-touch page faults on its
/// buffers (a fresh sampler's setup is several times a warm one's, on the demo and on a dense
/// mesh alike) and on the float BVH (its first rays cost twice the later ones), so its choice
/// serves this call only and the next similar call probes again.
ProbeVerdict probeVerdict(const ProbePart& bitmask, const ProbePart& rays, double bitmaskSetupMs, bool warm);

/// What decides whether the patches may swap roles (BitmaskOptions::swapRoles).
struct RoleSwapOptions {
    bool exact = true;        ///< exact mode (table mode is the paper's method as published)
    bool jittered = false;    ///< jitter shifts the source grid per receiver sample: not symmetric
    bool bumpy = false;       ///< heights displace the receiver's samples; a source is flat
    bool raysForced = false;  ///< the RayCast strategy answers the reference's way, bit for bit
};

/// Whether to sample with the patches' roles swapped: the bitmask's work follows (triangle,
/// receiver sample) pairs, so it backprojects onto the patch with more samples where that one
/// can be a source (at most kMaxSourceSamples, and at most 32 columns: the SIMD kernel's rows).
/// Segments are the same either way: the contract's test does not tell the ends apart.
bool swapPatchRoles(const Patch& source, const Patch& receiver, const RoleSwapOptions& options);

/// A receiver past kMaxSourceSamples cannot be a source; split into tiles of at most 32x32
/// samples, each can, and each has a narrower shaft too (32 source samples against a 64x64
/// receiver in a cluttered room: four swapped tiles take well under half the whole's time). The
/// tiles along each side (columns, rows) where the receiver is past kMaxSourceSamples and every
/// tile would swap roles with the source (more samples than it, and the options allow it); none
/// otherwise.
std::optional<std::pair<int, int>> receiverTilesToSwap(const Patch& source, const Patch& receiver,
                                                       const RoleSwapOptions& options);

/// One sampling configuration, as far as Auto's choice depends on it.
struct Configuration {
    Patch source, receiver;
    bool jittered = false;
    bool bumpy = false;
    bool floatKernel = false;   ///< the bitmask's SIMD kernel (its pairs cost a quarter of the double kernel's)
};

/// Whether a choice made on `measured` may serve `now`: the same sample grids and options,
/// both patches facing the same way within 10 degrees, their centres moved by less than a fifth
/// of the distance between them and their sizes within a fifth. A receiver dragged across a
/// wall keeps its choice; one moved to the floor does not.
bool similarConfiguration(const Configuration& measured, const Configuration& now);

/// A choice and how many more calls it may serve.
struct ProbeMemo {
    Configuration configuration;
    bool rays = false;
    int callsLeft = 0;
    bool measured = false;   ///< by a probe; else a clear-cut verdict of the estimate
};

/// A choice serves this many later calls on a similar configuration before Auto estimates (and,
/// where that is not clear-cut, measures) again.
constexpr int kProbeReuse = 7;

/// Auto's probe: how many of a receiver's `tiles` each method times at most: one in eight, but at
/// least four where the receiver has 16 or more (at 32x32 samples, two tiles each were too few to
/// tell the methods apart reliably).
std::size_t probeTilesPerMethod(std::size_t tiles);

} // namespace sightline::bitmask
