#pragma once
// Benchmarks every sampler against the raycast reference, side by side (docs/design.md §5): for each
// project, source sample count, receiver grid and method configuration, the median time of
// warm runs and the rays it gets wrong in each direction. A configuration's methods are timed in
// `repeat` interleaved rounds (in each, every method runs once untimed, then timed for at least
// Settings::minBatchMs), so that the machine's slow and fast spells fall on all of them alike.

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "visibility/ExactJudge.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::bench {

/// Method configurations: "raycast" (the exact reference), "embree-tuned" (the tuned float ray
/// tracer the speed targets are measured against, TunedEmbree.h), "cpu" (auto strategy),
/// "cpu-bitmask", "cpu-hybrid", "cpu-raycast" (the CPU sampler's strategies forced),
/// "cpu-table-WxH" (the paper's Hough table at W x H), "gl", "gl-table-WxH" (the GL sampler,
/// exact or with the Hough table, in a Settings::glBackend context), "hh"; "raycast-jitter",
/// "cpu-jitter", "gl-jitter": decorrelated sampling (§6.2, seed 1), compared with the reference
/// cast to the same jittered samples.
std::vector<std::string> parseMethods(const std::string& commaSeparated);   ///< throws sightline::Error

struct Settings {
    std::vector<std::string> projects;
    std::vector<std::string> methods = {"raycast", "cpu", "cpu-bitmask", "cpu-table-256x128"};
    std::vector<int> sourceCounts = {32, 128, 1024};
    std::vector<int> receiverSides = {32, 128};
    int repeat = 5;
    /// In each round, a method's timed runs go on until they have taken this long (at most
    /// kMaxRunsPerRound): a median of three sub-millisecond runs is mostly timing noise.
    double minBatchMs = 20.0;
    int threads = 0;
    gl::Backend glBackend = gl::Backend::OSMesa;   ///< headless context of "gl", "gl-table-WxH", "hh"
    /// Soft shadows (§8): when > 0, each receiver grid also gets a dense reference of the light
    /// fraction (denseLightFraction: denseSide x denseSide regular source samples by Embree), and
    /// rows report their light's mean absolute error against it.
    int denseSide = 0;
    bool allowOutsidePaths = false;   ///< project paths may leave their folders (base/PathRule.h)
};

struct Row {
    std::string project, method;
    int sourceSamples = 0, receiverSide = 0;
    double ms = 0.0;   ///< median of the timed runs (`runs`, in `repeat` rounds, each batch after an untimed run)
    /// Median processor time of the calling thread over the same runs. With Settings::threads
    /// 1 every method runs on that thread, and the figure is its work: a shared machine, where
    /// other jobs take turns on the cores, disturbs it far less than the wall time.
    double threadMs = 0.0;
    std::uint64_t rays = 0, blocked = 0;
    /// Where the method and the reference differ, each ray is judged (visibility/ExactJudge.h):
    /// a tie (docs/design.md §2: within 1e-5 m of an edge or an end) may go either way and is counted
    /// in `ties`; the rest are errors, in the method's direction. Rows with more than
    /// kMaxJudgedRays differences (table modes, which are inexact by design) are not judged: all
    /// their differences count as errors and `judged` is false.
    std::uint64_t wronglyBlocked = 0;   ///< method blocked, exactly free
    std::uint64_t wronglyFree = 0;      ///< method free, exactly blocked
    std::uint64_t ties = 0;             ///< differences on ties (either answer is right)
    bool judged = false;
    std::uint64_t referenceErrors = 0;  ///< differences where the judge sides with the method (a bug)
    double errorFraction() const { return rays ? double(wronglyBlocked + wronglyFree) / double(rays) : 0.0; }
    /// Light fraction per receiver sample (1 - blocked / S), mean absolute error against the
    /// reference with the same samples ...
    double lightMae = 0.0;
    /// ... and against the dense reference (Settings::denseSide; -1 when not computed).
    double denseMae = -1.0;
    /// embree-tuned: the traversal it kept (TunedTraversal::name), the fastest of those it timed.
    /// The CPU sampler: the strategy its last run took ("bitmask", "raycast", "hybrid", or
    /// "mixed" over tiles), with " swapped" where the patches swapped roles.
    std::string variant;
    int runs = 0;   ///< timed runs the medians are of (Settings::repeat, minBatchMs)
};

/// Rows with more differences from the reference than this are not judged ray by ray (the judge
/// is a brute force, far dearer a ray than the samplers it judges).
inline constexpr std::uint64_t kMaxJudgedRays = 50'000;

/// The most timed runs a method gets in a round (Settings::minBatchMs).
inline constexpr int kMaxRunsPerRound = 100;

/// The most square na x nb grid with na * nb == count and na >= nb (32 -> 8x4, 1024 -> 32x32).
std::pair<int, int> sourceGrid(int count);

/// Fills the row's wronglyBlocked, wronglyFree, ties, judged and referenceErrors from the rays
/// where `map` and the reference's `truth` differ, each judged by `judge()` (called only when
/// there is something to judge: a judge costs a pass over the scene's triangles).
void judgeDifferences(Row& row, const HiddenSampleMap& map, const HiddenSampleMap& truth,
                      const std::function<const ExactJudge&()>& judge);

/// Runs everything; `progress` (may be empty) is told of each finished row.
std::vector<Row> run(const Settings& settings, const std::function<void(const Row&)>& progress = {});

std::string toCsv(const std::vector<Row>& rows);

} // namespace sightline::bench
