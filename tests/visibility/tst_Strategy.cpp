// Auto's choice between the bitmask and ray casting (bitmask/Strategy.h) as plain functions of
// estimated and measured costs, on made-up inputs with known answers.

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "TestScenes.h"
#include "bitmask/Strategy.h"

using namespace sightline;
using namespace sightline::bitmask;
using sightline::test::xyPatch;

namespace {

/// Flat costs: 2 ns a pair whatever the pairs per ray, 100 ns a ray whatever the shaft.
const CostModel kModel{.setupNsPerTriangle = 200.0, .passNsPerPair = 2.0, .passFalloff = 0.0, .rayLogBase = std::log(100.0)};

CostEstimate estimate(std::uint64_t rays, std::uint64_t pairs, std::uint64_t triangles, int receiverSamples = 64 * 64)
{
    return {.rays = rays, .estimatedPairs = pairs, .estimatedTriangles = triangles, .floatKernel = true, .bumpy = false,
            .receiverSamples = receiverSamples};
}

} // namespace

TEST(Strategy, PredictsEachMethodFromItsUnits)
{
    const CostEstimate e = estimate(1'000'000, 4'000'000, 10'000);
    EXPECT_DOUBLE_EQ(predictedBitmaskMs(e, kModel), 1e-6 * (200.0 * 10'000 + 2.0 * 4'000'000));   // 10 ms
    EXPECT_NEAR(predictedRayMs(e, kModel), 100.0, 1e-9);
}

TEST(Strategy, PairsCostLessAsTheyCrowdARayAndRaysMoreInADeeperTree)
{
    CostModel m = kModel;
    m.passFalloff = 0.5;
    EXPECT_DOUBLE_EQ(m.passNs(4.0), 2.0);    // the reference point: 4 pairs a ray
    EXPECT_DOUBLE_EQ(m.passNs(16.0), 1.0);   // four times as many: half the cost each
    EXPECT_DOUBLE_EQ(m.passNs(0.0), m.passNs(0.01));
    // Each ray's cost is a product of powers: of the tree (1 + triangles), of 1 + pairs per ray
    // (and its square in the logarithm), of the receiver grid's side.
    m.rayLogTriangles = 0.5;
    EXPECT_NEAR(m.rayNs(99, 0.0, 1), 100.0 * 10.0, 1e-9);   // sqrt(1 + 99)
    m.rayLogTriangles = 0.0, m.rayLogSide = -1.0;
    EXPECT_NEAR(m.rayNs(99, 0.0, 64 * 64), 100.0 / 64.0, 1e-9);
    m.rayLogSide = 0.0, m.rayLogPairs = 1.0;
    EXPECT_NEAR(m.rayNs(0, std::exp(2.0) - 1.0, 1), 100.0 * std::exp(2.0), 1e-9);
    EXPECT_NEAR(m.rayNs(0, 1e9, 1), m.rayNs(0, std::exp(7.0) - 1.0, 1), 1e-9);   // clamped to the fitted range
    // ... and of e to the coverage (the part of the receiver a triangle's region covers, 0-1).
    m.rayLogPairs = 0.0, m.rayCoverage = -1.0;
    EXPECT_NEAR(m.rayNs(0, 0.0, 1, 0.5), 100.0 * std::exp(-0.5), 1e-9);
    EXPECT_NEAR(m.rayNs(0, 0.0, 1, 3.0), m.rayNs(0, 0.0, 1, 1.0), 1e-9);
    // predictedRayMs passes pairs / (triangles x receiver samples): 64 triangles each covering a
    // quarter of a 32x32 receiver.
    EXPECT_NEAR(predictedRayMs(estimate(1'000'000, 64 * 256, 64, 32 * 32), m), 1e-6 * 100.0 * std::exp(-0.25) * 1'000'000, 1e-9);
    m.rayCoverage = 0.0, m.rayLogPairs = 1.0;
    const CostEstimate e = estimate(1'000'000, 4'000'000, 1023);
    EXPECT_NEAR(predictedRayMs(e, m), 1e-6 * 100.0 * std::exp(std::log1p(4.0)) * 1'000'000, 1e-9);
    // The measured model: pairs cost less as they crowd a ray; rays cost more in a deeper tree,
    // and less where the pairs are so many that rays stop at their first hits (a dense mesh);
    // a finer receiver grid makes packets cheaper.
    const CostModel& measured = measuredCosts(true);
    EXPECT_LT(measured.passNs(100.0), measured.passNs(1.0));
    EXPECT_GT(measured.rayNs(50'000, 10.0, 1024), measured.rayNs(100, 10.0, 1024));
    EXPECT_LT(measured.rayNs(50'000, 300.0, 1024), measured.rayNs(50'000, 30.0, 1024));
    EXPECT_LT(measured.rayNs(50'000, 30.0, 64 * 64), measured.rayNs(50'000, 30.0, 32 * 32));
    // Pairs from a few walls that cover the receiver cost rays less than as many from clutter.
    EXPECT_LT(measured.rayNs(300, 10.0, 1024, 1.0), measured.rayNs(300, 10.0, 1024, 0.01));
}

TEST(Strategy, DecidesWhereOnePredictionIsUnderHalfTheOther)
{
    // 1M rays (100 ms by ray casting) against a bitmask of 10 ms: the bitmask.
    EXPECT_EQ(planFor(estimate(1'000'000, 4'000'000, 10'000), kModel), Plan::Bitmask);
    // 32k rays (3.2 ms) against the same bitmask: ray casting.
    EXPECT_EQ(planFor(estimate(32'000, 4'000'000, 10'000), kModel), Plan::RayCast);
    // 48 ms of bitmask against 100 ms of rays: just under half, clear-cut.
    EXPECT_EQ(planFor(estimate(1'000'000, 23'000'000, 10'000), kModel), Plan::Bitmask);
    // In between (60 against 100 ms): timed on a few tiles first.
    EXPECT_EQ(planFor(estimate(1'000'000, 29'000'000, 10'000), kModel), Plan::Probe);
    EXPECT_EQ(planFor(estimate(1'000'000, 70'000'000, 10'000), kModel), Plan::Probe);   // 141 against 100
}

TEST(Strategy, RaysTheInnerProxiesAnsweredCostRayCastingNothing)
{
    // A quarter of 1M rays still open (100 ms of rays): 25 ms, and the 10 ms bitmask still
    // wins; a tenth: 10 ms, timed; a twenty-fifth: ray casting. The bitmask's prediction is the same.
    CostEstimate e = estimate(1'000'000, 4'000'000, 10'000);
    e.openShare = 0.25;
    EXPECT_NEAR(predictedRayMs(e, kModel), 25.0, 1e-9);
    EXPECT_DOUBLE_EQ(predictedBitmaskMs(e, kModel), 10.0);
    EXPECT_EQ(planFor(e, kModel), Plan::Bitmask);
    e.openShare = 0.1;
    EXPECT_EQ(planFor(e, kModel), Plan::Probe);
    e.openShare = 0.04;
    EXPECT_EQ(planFor(e, kModel), Plan::RayCast);
}

TEST(Strategy, DoesNotProbeWhereAProbeCannotTell)
{
    // Too few receiver samples for a probe's tiles, a bumpy receiver (the probe's ray tiles would
    // need the heights), or bins too large to build for a probe: the cheaper prediction decides.
    CostEstimate small = estimate(1'000'000, 29'000'000, 10'000, 16 * 16);
    EXPECT_EQ(planFor(small, kModel), Plan::Bitmask);
    small.estimatedPairs = 70'000'000;
    EXPECT_EQ(planFor(small, kModel), Plan::RayCast);
    CostEstimate bumpy = estimate(1'000'000, 29'000'000, 10'000);
    bumpy.bumpy = true;
    EXPECT_EQ(planFor(bumpy, kModel), Plan::Bitmask);
    const CostEstimate huge = estimate(1'000'000'000, 40'000'000'000, 100'000);   // 80 s against 100 s
    EXPECT_EQ(planFor(huge, kModel), Plan::Bitmask);
}

TEST(Strategy, TheMeasuredModelsCostTheDoubleKernelMore)
{
    EXPECT_GT(measuredCosts(false).passNsPerPair, measuredCosts(true).passNsPerPair);
    EXPECT_EQ(measuredCosts(false).rayNs(10'000, 10.0, 1024), measuredCosts(true).rayNs(10'000, 10.0, 1024));
}

TEST(Strategy, AProbeTimesOneTileInEightButAtLeastFour)
{
    EXPECT_EQ(probeTilesPerMethod(256), 32u);   // 128x128 receiver samples
    EXPECT_EQ(probeTilesPerMethod(64), 8u);     // 64x64
    EXPECT_EQ(probeTilesPerMethod(16), 4u);     // 32x32: a quarter each
    EXPECT_EQ(probeTilesPerMethod(8), 2u);      // never more than half the receiver in all
}

TEST(Strategy, AProbeStopsOnceOneMethodIsClearlyFasterOrItHasCostEnough)
{
    // Tiles' shares (no units probed): 4 of 64 tiles each, batches of 4: not before two batches
    // of the bitmask.
    const double quarter = probeShare(0.0, 100.0, 16, 64);
    EXPECT_DOUBLE_EQ(quarter, 0.25);
    EXPECT_FALSE(probeIsDecided({4.0, 4.0 / 64}, 4, {10.0, 4.0 / 64}, 4, 4));
    // Ray tiles at 2.5 ms against bitmask tiles at 1 ms: decided.
    EXPECT_TRUE(probeIsDecided({8.0, 8.0 / 64}, 8, {10.0, 4.0 / 64}, 4, 4));
    // Within a factor of two, and the probe has cost under a tenth of the faster whole: go on.
    EXPECT_FALSE(probeIsDecided({8.0, 8.0 / 1000}, 8, {12.0, 8.0 / 1000}, 8, 4));
    // ... and once it has cost a tenth of it: stop.
    EXPECT_TRUE(probeIsDecided({8.0, 8.0 / 100}, 8, {12.0, 8.0 / 100}, 8, 4));
    // No setup: the wholes decide.
    EXPECT_TRUE(probeChoosesRays({10.0, 0.125}, {8.0, 0.125}, 0.0));
    EXPECT_FALSE(probeChoosesRays({8.0, 0.125}, {10.0, 0.125}, 0.0));
    EXPECT_FALSE(probeChoosesRays({8.0, 0.125}, {4.0, 0.0625}, 0.0));   // equal wholes: the bitmask
    // Rays 25% dearer (80 against 64 ms for the receiver), but the bitmask's setup took 20 ms:
    // rays, which later calls take without that setup.
    EXPECT_TRUE(probeChoosesRays({8.0, 0.125}, {10.0, 0.125}, 20.0));
    EXPECT_FALSE(probeChoosesRays({8.0, 0.125}, {10.0, 0.125}, 10.0));
}

TEST(Strategy, AProbeScalesEachMethodByTheWorkItsTilesHold)
{
    // Measured (rounded), whole calls taking 200-290 ms by rays and 260-340 by the bitmask: a
    // dense mesh at 1024 x 64x64, whose eight ray tiles of 64 held a fifth of the free rays and
    // took 35 ms, and whose eight bitmask tiles held a ninth of the bin entries and took 36 ms.
    // By tiles alone (an eighth each) the rays looked dearer: 280 against 288 + setup.
    {
        const ProbePart rays{35.0, probeShare(278000.0, 1400000.0, 8, 64)};
        const ProbePart bitmask{36.0, probeShare(91000.0, 853000.0, 8, 64)};
        EXPECT_NEAR(rays.share, 0.5 * (0.1986 + 0.125), 1e-3);
        EXPECT_NEAR(rays.wholeMs(), 216.0, 2.0);
        EXPECT_NEAR(bitmask.wholeMs(), 311.0, 2.0);
        EXPECT_TRUE(probeChoosesRays(bitmask, rays, 14.0));
        EXPECT_TRUE(probeVerdict(bitmask, rays, 14.0, true).restByRays);
    }
    // Another at 1024 x 32x32 (whole calls: rays 26-37 ms, bitmask 31-42): four ray tiles of 16
    // held a tenth of the free rays and took 5 ms, four bitmask tiles a quarter of the entries
    // and 5.6 ms, with a 9 ms setup. By units alone the rays came out at 48 ms and lost.
    {
        const ProbePart rays{5.0, probeShare(0.105, 1.0, 4, 16)};
        const ProbePart bitmask{5.6, probeShare(0.261, 1.0, 4, 16)};
        EXPECT_NEAR(rays.wholeMs(), 28.1, 0.5);
        EXPECT_TRUE(probeChoosesRays(bitmask, rays, 9.0));
        EXPECT_FALSE(probeChoosesRays(bitmask, ProbePart{5.0, 0.105}, 9.0));
    }
    // Tiles with no units probed (the bitmask's tiles held no occluder): the tiles' share.
    EXPECT_DOUBLE_EQ(probeShare(0.0, 500.0, 8, 64), 0.125);
    // No work anywhere: the tiles' share, and a whole of nothing costs nothing.
    EXPECT_DOUBLE_EQ(probeShare(0.0, 0.0, 4, 16), 0.25);
    EXPECT_DOUBLE_EQ((ProbePart{0.0, 0.0}).wholeMs(), 0.0);
}

TEST(Strategy, AProbeTimesBothMethodsOnNeighbouringTilesOverTheWholeReceiver)
{
    // 32x32 samples: 4x4 tiles, 4 pairs. 64x64: 8x8 tiles, 8 pairs.
    for (const auto& [tilesA, perMethod] : {std::pair<std::size_t, std::size_t>(4, 4), std::pair<std::size_t, std::size_t>(8, 8)}) {
        const std::size_t tiles = tilesA * tilesA;
        const ProbeTiles split = probeTiles(tiles, tilesA, perMethod);
        ASSERT_EQ(split.bitmask.size(), perMethod);
        ASSERT_EQ(split.rays.size(), perMethod);
        EXPECT_EQ(split.rest.size(), tiles - 2 * perMethod);
        // Every tile once.
        std::vector<int> seen(tiles, 0);
        for (const auto* list : {&split.bitmask, &split.rays, &split.rest})
            for (std::uint32_t t : *list)
                ++seen.at(t);
        EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(tiles));
        std::size_t bitmaskLeft = 0, rows = 0;
        std::vector<char> rowSeen(tilesA, 0);
        for (std::size_t k = 0; k < perMethod; ++k) {
            const std::uint32_t b = split.bitmask[k], r = split.rays[k];
            // Side by side in one row of the tile grid.
            EXPECT_EQ(b / tilesA, r / tilesA) << k;
            EXPECT_EQ(std::max(b, r) - std::min(b, r), 1u) << k;
            bitmaskLeft += b < r;
            rows += !rowSeen[b / tilesA];
            rowSeen[b / tilesA] = 1;
        }
        // Each method gets the left tile half the time, and the pairs spread over the rows.
        EXPECT_EQ(bitmaskLeft, perMethod / 2);
        EXPECT_GE(rows, tilesA / 2);
    }
    // A receiver one tile wide: pairs one above the other; an odd tile left over is not probed.
    const ProbeTiles column = probeTiles(5, 1, 2);
    for (std::size_t k = 0; k < 2; ++k)
        EXPECT_EQ(std::max(column.bitmask[k], column.rays[k]) - std::min(column.bitmask[k], column.rays[k]), 1u);
    EXPECT_EQ(column.rest.size(), 1u);
    // More pairs asked for than there are: all of them, nothing left but the odd tile.
    EXPECT_EQ(probeTiles(5, 1, 9).rest.size(), 1u);
}

TEST(Strategy, AColdProbeDecidesItsOwnCallOnly)
{
    // Rays 1 ms a tile, the bitmask 0.8 and a 20 ms setup, over 16 tiles: this call has paid its
    // setup, so its other tiles go by bitmask; later calls go by rays (16 ms against 32.8).
    const ProbeVerdict warm = probeVerdict({3.2, 0.25}, {4.0, 0.25}, 20.0, true);
    EXPECT_FALSE(warm.restByRays);
    EXPECT_TRUE(warm.memoRays);
    EXPECT_EQ(warm.memoCalls, kProbeReuse);
    // The same times measured on grids the sampler had not sampled before: the choice serves
    // no later call (the next one probes again, warm).
    const ProbeVerdict cold = probeVerdict({3.2, 0.25}, {4.0, 0.25}, 20.0, false);
    EXPECT_FALSE(cold.restByRays);
    EXPECT_EQ(cold.memoCalls, 0);
    // Rays cheaper per tile: the rest by rays as well.
    EXPECT_TRUE(probeVerdict({4.0, 0.25}, {3.2, 0.25}, 0.0, true).restByRays);
}

TEST(Strategy, AChoiceServesSimilarConfigurationsOnly)
{
    const Configuration wall{xyPatch(0, 32, 32), xyPatch(10, 64, 64), false, false};
    Configuration moved = wall;
    moved.receiver.corner += glm::dvec3(0.5, -0.3, 0.2);   // under a fifth of the 10 m between them
    EXPECT_TRUE(similarConfiguration(wall, moved));
    // The receiver now a floor: facing another way.
    Configuration floor = wall;
    floor.receiver.v = {0.0, 0.0, 1.0};
    floor.receiver.corner = {0.0, -1.0, 9.0};
    EXPECT_FALSE(similarConfiguration(wall, floor));
    // Turned by 5 degrees: similar; by 15: not.
    for (const auto& [degrees, similar] : {std::pair(5.0, true), std::pair(15.0, false)}) {
        Configuration turned = wall;
        const double a = degrees * M_PI / 180.0;
        turned.receiver.u = {std::cos(a), 0.0, std::sin(a)};
        EXPECT_EQ(similarConfiguration(wall, turned), similar) << degrees;
    }
    // Moved by 3 m of the 10: not.
    Configuration far = wall;
    far.receiver.corner.x += 3.0;
    EXPECT_FALSE(similarConfiguration(wall, far));
    // Twice the size: not.
    Configuration larger = wall;
    larger.receiver.u *= 2.0;
    EXPECT_FALSE(similarConfiguration(wall, larger));
    // Other grids or options: not.
    Configuration grid = wall;
    grid.receiver.na = 128;
    EXPECT_FALSE(similarConfiguration(wall, grid));
    Configuration jittered = wall;
    jittered.jittered = true;
    EXPECT_FALSE(similarConfiguration(wall, jittered));
}

TEST(Strategy, PatchesSwapRolesWhereTheReceiverHasMoreSamplesAndFitsASource)
{
    const Patch source = xyPatch(0, 16, 8), receiver = xyPatch(2, 32, 32);
    EXPECT_TRUE(swapPatchRoles(source, receiver, {}));
    EXPECT_FALSE(swapPatchRoles(source, receiver, {.exact = false}));
    EXPECT_FALSE(swapPatchRoles(source, receiver, {.jittered = true}));
    EXPECT_FALSE(swapPatchRoles(source, receiver, {.bumpy = true}));
    EXPECT_FALSE(swapPatchRoles(source, receiver, {.raysForced = true}));
    EXPECT_FALSE(swapPatchRoles(receiver, source, {}));                 // fewer receiver samples
    EXPECT_FALSE(swapPatchRoles(xyPatch(2, 32, 32), receiver, {}));      // as many
    EXPECT_FALSE(swapPatchRoles(source, xyPatch(2, 33, 31), {}));        // 33 columns
    EXPECT_FALSE(swapPatchRoles(source, xyPatch(2, 32, 33), {}));        // 1056 samples
    EXPECT_TRUE(swapPatchRoles(xyPatch(2, 1, 1), xyPatch(2, 2, 1), {}));
}

TEST(Strategy, WithSwappedRolesTheBitmaskWherePredictedNoDearerRaysWhereFarCheaperElseRaysAreTimed)
{
    // The swapped call cannot time the bitmask on tiles, and its ray prediction only runs low.
    const CostModel model{.setupNsPerTriangle = 1000.0, .passNsPerPair = 1.0, .passFalloff = 0.0};
    CostEstimate e{.rays = 32 * 1024, .estimatedPairs = 0, .estimatedTriangles = 0, .receiverSamples = 32,
                   .finerSamples = 1024, .swappedRoles = true};
    const double rayMs = predictedRayMs(e, model);
    const auto planAt = [&](double ratio) {
        e.estimatedTriangles = std::uint64_t(ratio * rayMs * 1000.0);   // 1 us each
        return planFor(e, model);
    };
    EXPECT_EQ(planAt(0.9 * kSwappedBitmaskClearCut), Plan::Bitmask);
    EXPECT_EQ(planAt(1.1 * kSwappedBitmaskClearCut), Plan::Probe);
    EXPECT_EQ(planAt(0.9 * kSwappedRaysClearCut), Plan::Probe);
    EXPECT_EQ(planAt(1.1 * kSwappedRaysClearCut), Plan::RayCast);
    // The same estimate with the roles kept: the usual rule (clear-cut at twice).
    e.swappedRoles = false;
    EXPECT_EQ(planAt(0.9 * kSwappedRaysClearCut), Plan::RayCast);
}

TEST(Strategy, TheSwappedProbeTimesAnEighthOfTheReceiverThenTheBitmaskUnlessRaysAreClearlyCheaper)
{
    std::vector<int> probe, rest;
    swappedProbeSamples(128, probe, rest);
    EXPECT_EQ(probe.size(), 16u);
    EXPECT_EQ(rest.size(), 112u);
    std::vector<int> all = probe;
    all.insert(all.end(), rest.begin(), rest.end());
    std::sort(all.begin(), all.end());
    for (int k = 0; k < 128; ++k)
        EXPECT_EQ(all[std::size_t(k)], k);
    EXPECT_TRUE(std::is_sorted(probe.begin(), probe.end()));
    EXPECT_GT(probe.back() - probe.front(), 64);   // spread over the receiver, not its first rows
    std::vector<int> again, restAgain;
    swappedProbeSamples(128, again, restAgain);
    EXPECT_EQ(again, probe);                       // the same samples every call
    swappedProbeSamples(5, probe, rest);
    EXPECT_EQ(probe.size(), 1u);
    EXPECT_EQ(rest.size(), 4u);
    // 16 of 128 samples in 1 ms: 8 ms for all. Rays without timing the bitmask only where that is
    // under kSwappedRaysUntimedBelow of the bitmask's prediction.
    EXPECT_DOUBLE_EQ(swappedRaysWholeMs(1.0, 16, 128), 8.0);
    EXPECT_DOUBLE_EQ(swappedRaysWholeMs(1.0, 0, 128), 128.0);   // nothing probed: no division by zero
    const double raysMs = swappedRaysWholeMs(1.0, 16, 128);
    EXPECT_EQ(swappedRaysOrTimeBitmask(1.01 * 8.0 / kSwappedRaysUntimedBelow, raysMs), SwappedVerdict::Rays);
    EXPECT_EQ(swappedRaysOrTimeBitmask(0.99 * 8.0 / kSwappedRaysUntimedBelow, raysMs), SwappedVerdict::TimeBitmask);
    EXPECT_EQ(swappedRaysOrTimeBitmask(1.0, raysMs), SwappedVerdict::TimeBitmask);   // predicted cheap
    // Timed: rays for later calls only where cheaper than the bitmask's setup and pass together,
    // the probe's rays weighed down by what they run high (cluttered-rooms-12 at 32 x 32²: the
    // probe's rays 5.9 ms, the bitmask 1.6 + 1.1; dense-mesh-8 at 128 x 32²: 10.1 against 13.6).
    EXPECT_FALSE(swappedMeasuredChoosesRays(5.9, 1.6, 1.1));
    EXPECT_TRUE(swappedMeasuredChoosesRays(10.1, 4.1, 9.5));
    EXPECT_TRUE(swappedMeasuredChoosesRays(5.4, 2.5, 2.5));    // within the probe's bias: rays
    EXPECT_FALSE(swappedMeasuredChoosesRays(kProbeRaysOverestimate * 5.0, 2.5, 2.5));   // a tie: the bitmask
}

TEST(Strategy, ARaysVerdictThatCostABitmaskCallServesLongEnoughToSpreadIt)
{
    // The timed bitmask (15 ms) spread over later calls by rays (6 ms each) at most 5% of theirs:
    // ceil(15 / 0.3) = 50 calls.
    EXPECT_EQ(swappedRaysMemoCalls(6.0, 15.0), 50);
    const double spread = 15.0 / (double(swappedRaysMemoCalls(6.0, 15.0)) * 6.0);
    EXPECT_LE(spread, kSwappedProbeShare);
    // A bitmask barely dearer than the rays: never fewer than the usual reuse.
    EXPECT_EQ(swappedRaysMemoCalls(6.0, 0.1), kProbeReuse);
    // One far dearer, or rays that cost nothing: capped, so a drifting configuration is looked at again.
    EXPECT_EQ(swappedRaysMemoCalls(1.0, 1000.0), kMaxSwappedReuse);
    EXPECT_EQ(swappedRaysMemoCalls(0.0, 5.0), kMaxSwappedReuse);
}

TEST(Strategy, ReceiversPastASourcesSamplesSplitIntoTilesThatEachSwap)
{
    const Patch source = xyPatch(0, 8, 4);
    EXPECT_FALSE(receiverTilesToSwap(source, xyPatch(2, 32, 32), {}));   // swaps whole
    EXPECT_EQ(receiverTilesToSwap(source, xyPatch(2, 64, 64), {}), std::pair(2, 2));
    EXPECT_EQ(receiverTilesToSwap(source, xyPatch(2, 70, 45), {}), std::pair(3, 2));
    EXPECT_EQ(receiverTilesToSwap(source, xyPatch(2, 128, 32), {}), std::pair(4, 1));
    EXPECT_FALSE(receiverTilesToSwap(source, xyPatch(2, 64, 64), {.jittered = true}));
    EXPECT_FALSE(receiverTilesToSwap(source, xyPatch(2, 64, 64), {.raysForced = true}));
    // Every tile must have more samples than the source: 1024 source samples never split.
    EXPECT_FALSE(receiverTilesToSwap(xyPatch(0, 32, 32), xyPatch(2, 64, 64), {}));
    // 33x33 splits into tiles of 16-17 x 16-17 (256 samples at least): a 16x16 source does not.
    EXPECT_EQ(receiverTilesToSwap(xyPatch(0, 16, 15), xyPatch(2, 33, 33), {}), std::pair(2, 2));
    EXPECT_FALSE(receiverTilesToSwap(xyPatch(0, 16, 16), xyPatch(2, 33, 33), {}));
}
