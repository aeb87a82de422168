#pragma once
// What coarse occluders cost and save on a pair, measured in one run: for each triangle count, the
// level with its dense meshes (or one object's) simplified to that count (project/CoarseOccluders.h,
// closest kind), sampled exactly by the CPU bitmask sampler like the original, and the rays the
// two answer differently. `sightline-cli coarse --sweep` charts it to PNG and the editor's
// Coarse Occluder dialog on screen (report/CoarseChart.h, through coarseChartData), the same figures.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "visibility/Patch.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"

namespace sightline {

struct CoarseSweepPoint {
    std::size_t asked = 0;        ///< the triangle count asked for each simplified mesh
    std::size_t triangles = 0;    ///< the level's triangles after (the decimater may stop short)
    double ms = 0.0;              ///< exact sampling, median of the repeats
    std::uint64_t falseBlocked = 0;   ///< blocked only by the coarse level
    std::uint64_t falseFree = 0;      ///< blocked only by the original

    std::uint64_t disagreeing() const { return falseBlocked + falseFree; }
};

struct CoarseSweep {
    std::size_t triangles = 0;    ///< the original level's
    double ms = 0.0;              ///< the original's exact sampling, median of the repeats
    std::uint64_t rays = 0;
    std::vector<CoarseSweepPoint> points;   ///< one per count asked, in the order asked
};

struct CoarseSweepRequest {
    std::vector<std::size_t> counts;          ///< triangle counts, each 4..1e8
    std::optional<std::size_t> instance;      ///< only this instance's mesh; else every mesh above the count
    int threads = 0;                          ///< 0: all cores
    int repeat = 3;                           ///< timed samplings per level, after one untimed
    /// Called after each level measured (points so far); false stops the sweep early.
    std::function<bool(const CoarseSweep&)> progress;
};

/// One coarse level against the original on the pair: both sampled exactly, side by side.
struct CoarseComparison {
    double originalMs = 0.0, ms = 0.0;   ///< medians of the repeats
    std::uint64_t rays = 0;
    std::uint64_t falseBlocked = 0, falseFree = 0;
    std::uint64_t disagreeing() const { return falseBlocked + falseFree; }
};
CoarseComparison compareCoarseLevel(const Scene& original, const Scene& coarse, const Patch& source, const Patch& receiver,
                                    const ReceiverHeights* heights, int threads, int repeat);

/// Throws sightline::Error for an invalid pair, a count out of range or an instance `scene` does
/// not have.
CoarseSweep sweepCoarseOccluders(const Scene& scene, const Patch& source, const Patch& receiver,
                                 const ReceiverHeights* heights, const CoarseSweepRequest& request);

/// The fewest triangles, to within `resolution` (a ratio above 1), whose stand-ins answer at most
/// `tolerance` of the pair's rays differently, checked by the exact sampler on the pair: a
/// bisection over the count (on a log scale) between 4 and the largest mesh's triangles, each step
/// a coarse level sampled against the original's answer. Not every count below the result is
/// refused (the disagreement need not fall steadily with the count), but the result holds: its
/// point is measured. `points` holds every count tried, in the order tried (ms: one untimed
/// sampling each); `chosen` the one kept (none when only the full meshes meet the tolerance).
struct CoarseToleranceFit {
    CoarseSweep tried;
    std::optional<CoarseSweepPoint> chosen;
};
struct CoarseToleranceRequest {
    double tolerance = 0.001;                 ///< a fraction of the rays, in [0, 1]
    std::optional<std::size_t> instance;      ///< only this instance's mesh; else every mesh above the count
    int threads = 0;
    double resolution = 1.05;
    /// Checked before each count; true ends the search with what it found so far.
    const std::atomic<bool>* cancel = nullptr;
};
/// Throws sightline::Error for an invalid pair, a tolerance outside [0, 1], an instance `scene`
/// does not have, or a level (or instance) without a mesh of more than 8 triangles.
CoarseToleranceFit fitCoarseToTolerance(const Scene& scene, const Patch& source, const Patch& receiver,
                                        const ReceiverHeights* heights, const CoarseToleranceRequest& request);

/// The counts a sweep of a mesh of `triangles` tries when none are given: halving from a half of
/// it down to 100 (at most 8 counts).
std::vector<std::size_t> defaultSweepCounts(std::size_t triangles);

} // namespace sightline
