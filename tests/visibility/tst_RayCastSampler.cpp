// The Embree reference sampler against closed-form answers and an independent brute-force caster.
#include <random>

#include <gtest/gtest.h>

#include "BruteForceCaster.h"
#include "TestScenes.h"
#include "visibility/Error.h"
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
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.5f, 1.5f), z(0.2f, 1.8f), s(-0.3f, 0.3f);
    Mesh soup;
    for (int t = 0; t < 300; ++t) {
        const glm::vec3 a(u(rng), u(rng), z(rng));
        soup.positions.insert(soup.positions.end(), {a, a + glm::vec3(s(rng), s(rng), s(rng)),
                                                     a + glm::vec3(s(rng), s(rng), s(rng))});
        soup.indices.insert(soup.indices.end(), {3u * t, 3u * t + 1, 3u * t + 2});
    }
    const RayCastScene caster(sceneOf({soup}));
    const Patch source = xyPatch(0, 32, 32), receiver = xyPatch(2, 16, 16);
    const HiddenSampleMap packets = caster.sample(source, receiver, {.packets = true, .threads = 0});
    EXPECT_EQ(packets, caster.sample(source, receiver, {.packets = false, .threads = 0}));
    EXPECT_EQ(packets, caster.sample(source, receiver, {.packets = true, .threads = 1}));
    EXPECT_GT(packets.blockedCount(), 0u);
    EXPECT_LT(packets.blockedCount(), packets.rayCount());
}

namespace {

/// A random valid non-parallel patch pair and a soup of triangles of mixed sizes in and around
/// the shaft, some crossing the patch planes.
struct RandomCase {
    Scene scene;
    Patch source, receiver;
};

RandomCase randomCase(unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto range = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    RandomCase c;
    // Source near the origin facing +Z, tilted; receiver 3-5 m away, tilted the other way.
    c.source.corner = {range(-0.2, 0.2), range(-0.2, 0.2), 0.0};
    c.source.u = {range(0.6, 1.5), 0.0, range(-0.3, 0.3)};
    c.source.v = {range(-0.2, 0.2), range(0.6, 1.5), range(-0.3, 0.3)};
    c.source.na = 1 + int(rng() % 12);
    c.source.nb = 1 + int(rng() % 12);
    const double depth = range(3.0, 5.0);
    c.receiver.corner = {range(-1.0, 1.0), range(-1.0, 1.0), depth};
    c.receiver.u = {range(0.8, 2.5), range(-0.4, 0.4), range(-0.5, 0.5)};
    c.receiver.v = {0.0, range(0.8, 2.5), range(-0.5, 0.5)};
    c.receiver.na = 1 + int(rng() % 10);
    c.receiver.nb = 1 + int(rng() % 10);

    Mesh soup;
    auto addTriangle = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 cc) {
        const auto base = std::uint32_t(soup.positions.size());
        soup.positions.insert(soup.positions.end(), {glm::vec3(a), glm::vec3(b), glm::vec3(cc)});
        soup.indices.insert(soup.indices.end(), {base, base + 1, base + 2});
    };
    auto point = [&](double zLo, double zHi) { return glm::dvec3(range(-1.0, 2.5), range(-1.0, 2.5), range(zLo, zHi)); };
    auto jitter = [&](double size) { return glm::dvec3(range(-size, size), range(-size, size), range(-size, size)); };
    for (int t = 0; t < 60; ++t) {   // tiny
        const glm::dvec3 p = point(0.3, depth - 0.3);
        addTriangle(p, p + jitter(0.05), p + jitter(0.05));
    }
    for (int t = 0; t < 25; ++t) {   // medium
        const glm::dvec3 p = point(0.3, depth - 0.3);
        addTriangle(p, p + jitter(0.6), p + jitter(0.6));
    }
    for (int t = 0; t < 3; ++t) {    // huge, possibly crossing both patch planes
        const glm::dvec3 p = point(-1.0, depth + 1.0);
        addTriangle(p, p + jitter(6.0), p + jitter(6.0));
    }
    // One crossing the source plane, one crossing the receiver plane.
    addTriangle({0.3, 0.3, -0.5}, {0.9, 0.4, 0.7}, {0.5, 1.0, 0.4});
    addTriangle({0.0, 0.5, depth + 0.5}, {1.5, 0.6, depth - 0.8}, {0.6, 1.8, depth - 0.2});
    c.scene.addMeshInstance(std::move(soup));
    return c;
}

} // namespace

TEST(RayCastSampler, AgreesWithBruteForceOnRandomScenes)
{
    int checked = 0;
    std::uint64_t blocked = 0, rays = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        const RandomCase c = randomCase(seed);
        try {
            validatePatchPair(c.source, c.receiver);
        } catch (const Error&) {
            continue;   // the generator made an invalid pair; the rest of the test covers refusal
        }
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
