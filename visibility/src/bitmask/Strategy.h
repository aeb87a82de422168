#pragma once
// Internal to the CPU bitmask sampler: how Auto chooses between the bitmask and ray casting.
//
// The bitmask's cost follows (occluder, receiver sample) pairs after the narrowed shaft, ray
// casting's follows the rays; neither is known before sampling. Auto estimates the pairs from a
// sample of the triangles, decides where the estimate is clear-cut, and otherwise measures both
// methods on a few random tiles (their rows are final either way) and finishes with the faster.
// A measured choice serves later calls on a similar configuration (the editor and animations
// sample slowly changing ones). The decisions are plain functions of measured and estimated
// costs, tested on their own (tst_Strategy).

#include <array>
#include <cstdint>

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
};

/// What a unit of each method's work costs, fitted to runs on these 2-core machines over the
/// demo, its floor, the dense mesh, few occluders and the twelve bench scenes at 64-1024 sources
/// and 32-128 receiver samples (README, "Auto's cost model"):
/// - the bitmask: setup per triangle in the shaft, and its pass per estimated pair, which falls
///   as the pairs per ray grow (the narrowed shaft skips more of them once a tile is blocked):
///   passNsPerPair * (pairs per ray / 4)^-passFalloff;
/// - ray casting: per ray, growing with the BVH's depth, rayNsPerLevel * log2(1 + triangles in
///   the shaft) - rayNsOffset (at least minRayNs), plus a share of the bitmask's pass (the fit's
///   way of saying that a crowded shaft costs rays more candidates each, not only a deeper walk),
///   plus rayNsPerReceiverSample per receiver sample (with few source samples a packet's rays
///   share little of the traversal).
struct CostModel {
    double setupNsPerTriangle = 0.0;
    double rayNsPerReceiverSample = 0.0;   ///< ray casting's work per receiver sample (its packets)
    double passNsPerPair = 0.0;
    double passFalloff = 0.0;
    double rayNsPerLevel = 0.0;
    double rayNsOffset = 0.0;
    double minRayNs = 0.0;
    double rayPassShare = 0.0;

    /// The bitmask pass's cost per pair for this many pairs per ray.
    double passNs(double pairsPerRay) const;
    /// Ray casting's cost per ray with this many triangles in the shaft.
    double rayNs(std::uint64_t trianglesInShaft) const;
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
/// huge), else the cheaper prediction.
Plan planFor(const CostEstimate& estimate, const CostModel& model);

/// While probing: whether enough is known to stop, from the tiles done by each method and their
/// times, and the whole receiver's tile count and the batch size.
bool probeIsDecided(std::size_t bitmaskTiles, double bitmaskMs, std::size_t rayTiles, double rayMs, std::size_t tiles,
                    std::size_t batch);

/// The probe's verdict: ray casting when a whole call by rays (its cost per tile times the
/// receiver's `tiles`) would cost less than a whole call by the bitmask, which is its cost per
/// tile times the tiles plus its setup (`bitmaskSetupMs`: clipping, regions, binning). The choice
/// serves later calls (ProbeMemo), which by rays skip that setup altogether.
bool probeChoosesRays(std::size_t bitmaskTiles, double bitmaskMs, std::size_t rayTiles, double rayMs, std::size_t tiles,
                      double bitmaskSetupMs);

/// One sampling configuration, as far as Auto's choice depends on it.
struct Configuration {
    Patch source, receiver;
    bool jittered = false;
    bool bumpy = false;
};

/// Whether a choice measured on `measured` may serve `now`: the same sample grids and options,
/// both patches facing the same way within 10 degrees, their centres moved by less than a fifth
/// of the distance between them and their sizes within a fifth. A receiver dragged across a
/// wall keeps its choice; one moved to the floor does not.
bool similarConfiguration(const Configuration& measured, const Configuration& now);

/// A measured choice and how many more calls it may serve.
struct ProbeMemo {
    Configuration configuration;
    bool rays = false;
    int callsLeft = 0;
};

/// A probe's choice serves this many later calls on a similar configuration before Auto
/// measures again.
constexpr int kProbeReuse = 7;

/// Auto's probe: how many of a receiver's `tiles` each method times at most: one in eight, but at
/// least four where the receiver has 16 or more (at 32x32 samples, two tiles each were too few to
/// tell the methods apart reliably).
std::size_t probeTilesPerMethod(std::size_t tiles);

} // namespace sightline::bitmask
