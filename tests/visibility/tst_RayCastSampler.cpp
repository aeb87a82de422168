// The Embree reference sampler against closed-form answers and an independent brute-force caster.
#include <random>

#include <gtest/gtest.h>

#include "BruteForceCaster.h"
#include "TestScenes.h"
#include "base/Error.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
using namespace sightline::test;

namespace {

/// Pairs (a_s, a_r) of an n-sample axis whose midpoint (a_s + a_r + 1) / 2n lies strictly inside
/// (lo, hi): the per-axis count for an occluder halfway between two identical parallel patches.
std::uint64_t midpointPairs(int n, double lo, double hi)
{
    std::uint64_t count = 0;
    for (int m = 0; m <= 2 * n - 2; ++m) {
        const double mid = (m + 1) / (2.0 * n);
        if (mid > lo && mid < hi)
            count += std::uint64_t(std::min(m, 2 * n - 2 - m) + 1);
    }
    return count;
}

} // namespace

TEST(RayCastSampler, EmptySceneBlocksNothing)
{
    const RayCastScene caster(Scene{});
    const HiddenSampleMap map = caster.sample(xyPatch(0, 32, 32), xyPatch(2, 32, 32));
    EXPECT_EQ(map.rayCount(), 1024u * 1024u);
    EXPECT_EQ(map.blockedCount(), 0u);
}

TEST(RayCastSampler, WallLargerThanShaftBlocksEverything)
{
    const Scene scene = sceneOf({quad({-10, -10, 1}, {20, 0, 0}, {0, 20, 0})});
    const RayCastScene caster(scene);
    const HiddenSampleMap map = caster.sample(xyPatch(0, 32, 32), xyPatch(2, 32, 32));
    EXPECT_EQ(map.blockedCount(), map.rayCount());
}

TEST(RayCastSampler, SmallQuadHalfwayBlocksTheCountedPairs)
{
    // Occluder [0.31, 0.62] x [0.27, 0.83] at z = 1, patches at z = 0 and z = 2: a ray is blocked
    // iff its midpoint lies inside, and the two axes count independently.
    const int n = 32;
    const Scene scene = sceneOf({quad({0.31f, 0.27f, 1}, {0.31f, 0, 0}, {0, 0.56f, 0})});
    const RayCastScene caster(scene);
    const HiddenSampleMap map = caster.sample(xyPatch(0, n, n), xyPatch(2, n, n));
    const std::uint64_t expected = midpointPairs(n, 0.31, 0.62) * midpointPairs(n, 0.27, 0.83);
    EXPECT_GT(expected, 0u);
    EXPECT_EQ(map.blockedCount(), expected);
}

TEST(RayCastSampler, HalfPlaneEdgeBlocksExactlyTheRaysOnOneSide)
{
    // Half-plane x < 0.437 at z = 1; source at z = 0, receiver at z = 3 (4x wider receiver grid
    // than source grid, non-square grids). A ray crosses z = 1 at x = xs + (xr - xs) / 3.
    const double edge = 0.437;
    const Scene scene = sceneOf({quad({-50, -50, 1}, {50 + float(edge), 0, 0}, {0, 100, 0})});
    const RayCastScene caster(scene);
    const Patch source = xyPatch(0, 13, 7);
    const Patch receiver = xyPatch(3, 52, 9);
    const HiddenSampleMap map = caster.sample(source, receiver);
    std::uint64_t expected = 0, mismatches = 0;
    for (int j = 0; j < receiver.sampleCount(); ++j)
        for (int i = 0; i < source.sampleCount(); ++i) {
            const double xs = source.sample(i).x, xr = receiver.sample(j).x;
            const double x = xs + (xr - xs) / 3.0;
            ASSERT_GT(std::abs(x - edge), 1e-4) << "test set-up: a ray grazes the edge";
            const bool blocked = x < edge;
            expected += blocked;
            mismatches += blocked != map.blocked(j, i);
        }
    EXPECT_GT(expected, 0u);
    EXPECT_LT(expected, map.rayCount());
    EXPECT_EQ(mismatches, 0u);
    EXPECT_EQ(map.blockedCount(), expected);
}

TEST(RayCastSampler, LargeReceiverGrid)
{
    // 512 x 512 receiver samples against the half-plane; every ray checked by formula.
    const double edge = 0.5003;
    const Scene scene = sceneOf({quad({-50, -50, 1}, {50 + float(edge), 0, 0}, {0, 100, 0})});
    const RayCastScene caster(scene);
    const Patch source = xyPatch(0, 2, 2);
    const Patch receiver = xyPatch(2, 512, 512);
    const HiddenSampleMap map = caster.sample(source, receiver);
    std::uint64_t mismatches = 0;
    for (int j = 0; j < receiver.sampleCount(); ++j)
        for (int i = 0; i < source.sampleCount(); ++i) {
            const double x = 0.5 * (source.sample(i).x + receiver.sample(j).x);
            if (std::abs(x - edge) > 1e-5)
                mismatches += (x < edge) != map.blocked(j, i);
        }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_GT(map.blockedCount(), map.rayCount() / 4);
}

TEST(RayCastSampler, SurfacesAtTheSegmentEndsDoNotBlock)
{
    // The source lies on a wall (coplanar), the receiver in front of another wall: the segments
    // start and end on surfaces but cross nothing strictly between.
    const Scene scene = sceneOf({quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0}), quad({-5, -5, 2}, {10, 0, 0}, {0, 10, 0})});
    const RayCastScene caster(scene);
    EXPECT_EQ(caster.sample(xyPatch(0, 8, 8), xyPatch(2, 8, 8)).blockedCount(), 0u);
}

TEST(RayCastSampler, PacketsSingleRaysAndThreadCountsAgree)
{
    const Mesh soup = randomSoup(7, 300, -0.5f, 1.5f, 0.2f, 1.8f, 0.3f);
    const RayCastScene caster(sceneOf({soup}));
    const Patch source = xyPatch(0, 32, 32), receiver = xyPatch(2, 16, 16);
    const HiddenSampleMap packets = caster.sample(source, receiver, {.packets = true, .threads = 0});
    EXPECT_EQ(packets, caster.sample(source, receiver, {.packets = false, .threads = 0}));
    EXPECT_EQ(packets, caster.sample(source, receiver, {.packets = true, .threads = 1}));
    EXPECT_GT(packets.blockedCount(), 0u);
    EXPECT_LT(packets.blockedCount(), packets.rayCount());
}


TEST(RayCastSampler, AgreesWithBruteForceOnRandomScenes)
{
    int checked = 0;
    std::uint64_t blocked = 0, rays = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        const RandomCase c = randomCase(seed);
        if (!c.valid())
            continue;   // the generator made an invalid pair; refusal is tested separately
        ++checked;
        const RayCastScene caster(c.scene);
        const HiddenSampleMap map = caster.sample(c.source, c.receiver);
        const BruteForceMap reference = bruteForceSample(worldTriangles(c.scene), c.source, c.receiver);
        EXPECT_EQ(mismatchesOutsideGrazing(map, reference), 0u)
            << "seed " << seed << ": " << map.blockedCount() << " blocked vs brute force "
            << reference.blocked.blockedCount() << ", grazing " << reference.grazing.blockedCount();
        EXPECT_LE(reference.grazing.blockedCount(), map.rayCount() / 100) << "seed " << seed;
        blocked += map.blockedCount();
        rays += map.rayCount();
    }
    EXPECT_GE(checked, 30);
    // The scenes are neither empty nor solid: both answers are exercised.
    EXPECT_GT(blocked, rays / 10) << blocked << " of " << rays;
    EXPECT_LT(blocked, rays * 9 / 10) << blocked << " of " << rays;
}

TEST(RayCastSampler, RefusesInvalidPatchPairs)
{
    const RayCastScene caster(Scene{});
    // Receiver crossing the source plane.
    Patch receiver = xyPatch(2, 8, 8);
    receiver.corner = {0, 0, -1};
    receiver.v = {0, 0, 3};
    EXPECT_THROW(caster.sample(xyPatch(0, 8, 8), receiver), Error);
    // Coplanar patches.
    EXPECT_THROW(caster.sample(xyPatch(0, 8, 8), xyPatch(0, 8, 8)), Error);
    // Sample counts.
    EXPECT_THROW(caster.sample(xyPatch(0, 0, 8), xyPatch(2, 8, 8)), Error);
    EXPECT_THROW(caster.sample(xyPatch(0, 50, 40), xyPatch(2, 8, 8)), Error);   // 2000 source samples
    EXPECT_THROW(caster.sample(xyPatch(0, 8, 8), xyPatch(2, 0, 0)), Error);
    // Degenerate and non-finite.
    Patch flat = xyPatch(0, 8, 8);
    flat.v = flat.u;
    EXPECT_THROW(caster.sample(flat, xyPatch(2, 8, 8)), Error);
    Patch nan = xyPatch(0, 8, 8);
    nan.corner.x = std::nan("");
    EXPECT_THROW(caster.sample(nan, xyPatch(2, 8, 8)), Error);
}
