// A bumpy receiver given as a height field (Eisemann & Décoret §8): validation, closed forms, and
// the exact CPU bitmask sampler against the Embree reference and an independent brute force.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "BruteForceCaster.h"
#include "TestScenes.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/RayCastSampler.h"
#include "visibility/ReceiverHeights.h"

using namespace sightline;
using namespace sightline::test;

namespace {

/// The brute force of BruteForceCaster.h with the receiver ends at their displaced positions.
BruteForceMap bumpyBruteForce(const WorldTriangles& tris, const Patch& source, const Patch& receiver,
                              const ReceiverHeights& heights, const SourceJitter& jitter = {})
{
    BruteForceMap out{HiddenSampleMap(source.sampleCount(), receiver.na, receiver.nb),
                      HiddenSampleMap(source.sampleCount(), receiver.na, receiver.nb)};
    for (int j = 0; j < receiver.sampleCount(); ++j) {
        const glm::dvec3 end = displacedReceiverSample(source, receiver, heights, j);
        for (int i = 0; i < source.sampleCount(); ++i) {
            const SegmentResult r = bruteForceSegment(tris, end, source.sample(i) + jitter.shift(source, j));
            if (r.blocked)
                out.blocked.setBlocked(j, i);
            if (r.margin < 1e-5)
                out.grazing.setBlocked(j, i);
        }
    }
    return out;
}

/// A smooth random height field over the receiver grid (two waves and a bump), with values in
/// [lo, hi], plus a little per-sample noise so that neighbouring samples differ.
ReceiverHeights randomHeights(unsigned seed, const Patch& receiver, double lo, double hi)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double f1 = 1.0 + 5.0 * unit(rng), f2 = 1.0 + 5.0 * unit(rng), p1 = 6.3 * unit(rng), p2 = 6.3 * unit(rng);
    const double cx = unit(rng), cy = unit(rng);
    ReceiverHeights heights;
    for (int j = 0; j < receiver.sampleCount(); ++j) {
        const double x = (j % receiver.na + 0.5) / receiver.na, y = (j / receiver.na + 0.5) / receiver.nb;
        const double wave = 0.3 * std::sin(f1 * x + p1) + 0.25 * std::sin(f2 * y + p2) +
                            0.6 * std::exp(-10.0 * ((x - cx) * (x - cx) + (y - cy) * (y - cy))) + 0.15 * unit(rng);
        heights.metres.push_back(lo + (hi - lo) * std::clamp((wave + 0.55) / 1.65, 0.0, 1.0));
    }
    return heights;
}

/// randomCase (TestScenes.h) plus occluders where bumps make the difference: triangles around
/// displaced receiver samples (reaching into the bump range, some crossing the receiver plane),
/// and a "floor" in the receiver's own plane that hides the samples below it.
RandomCase bumpyCase(unsigned seed)
{
    RandomCase c = randomCase(seed);
    std::mt19937 rng(seed * 7919u + 13u);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Patch& r = c.receiver;
    const glm::dvec3 n = receiverNormalTowardSource(c.source, r);
    Mesh extra;
    auto add = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 d) {
        const auto base = std::uint32_t(extra.positions.size());
        extra.positions.insert(extra.positions.end(), {glm::vec3(a), glm::vec3(b), glm::vec3(d)});
        extra.indices.insert(extra.indices.end(), {base, base + 1, base + 2});
    };
    auto jitter = [&](double size) {
        return glm::dvec3(size * (2 * unit(rng) - 1), size * (2 * unit(rng) - 1), size * (2 * unit(rng) - 1));
    };
    for (int t = 0; t < 30; ++t) {
        const glm::dvec3 p = r.corner + unit(rng) * r.u + unit(rng) * r.v + (-0.9 + 2.0 * unit(rng)) * n;
        const double size = t < 20 ? 0.25 : 0.9;
        add(p, p + jitter(size), p + jitter(size));
    }
    // A floor in the receiver plane, slightly larger than the patch, over one half of it.
    if (seed % 2 == 0) {
        const glm::dvec3 o = r.corner - 0.2 * r.u - 0.2 * r.v;
        add(o, o + 1.4 * r.u, o + 1.4 * r.v);
    }
    c.scene.addMeshInstance(std::move(extra));
    return c;
}

/// The rectangle [x0, x1] x [y0, y1] at height z, from exact corners (no float sums, so that
/// rectangles sharing an edge share its vertices).
Mesh rectangle(float x0, float x1, float y0, float y1, float z)
{
    Mesh m;
    m.name = "rectangle";
    m.positions = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

/// Rays of `map` blocked where the brute force is clear or clear where it is blocked, outside
/// the brute force's grazing rays.
std::uint64_t mismatches(const HiddenSampleMap& map, const BruteForceMap& reference)
{
    return mismatchesOutsideGrazing(map, reference);
}

} // namespace

TEST(ReceiverHeights, DisplacementIsAlongTheNormalTowardTheSource)
{
    const Patch source = xyPatch(0, 4, 4);
    Patch receiver = xyPatch(3, 4, 4);
    EXPECT_EQ(receiverNormalTowardSource(source, receiver), glm::dvec3(0, 0, -1));
    std::swap(receiver.u, receiver.v);   // the other orientation: the normal still faces the source
    EXPECT_EQ(receiverNormalTowardSource(source, receiver), glm::dvec3(0, 0, -1));
    ReceiverHeights heights{std::vector<double>(16, 0.0)};
    heights.metres[5] = 1.25;
    heights.metres[6] = -0.5;
    EXPECT_EQ(displacedReceiverSample(source, receiver, heights, 5), receiver.sample(5) + glm::dvec3(0, 0, -1.25));
    EXPECT_EQ(displacedReceiverSample(source, receiver, heights, 6), receiver.sample(6) + glm::dvec3(0, 0, 0.5));
    EXPECT_EQ(displacedReceiverSample(source, receiver, ReceiverHeights{}, 6), receiver.sample(6));
}

TEST(ReceiverHeights, RefusesInvalidHeights)
{
    const Patch source = xyPatch(0, 4, 4), receiver = xyPatch(3, 5, 6);
    const Scene scene = sceneOf({quad({-10, -10, 1}, {20, 0, 0}, {0, 20, 0})});
    const RayCastScene caster(scene);
    const CpuBitmaskSampler sampler(scene);
    auto refusedEverywhere = [&](const ReceiverHeights& heights, const std::string& expect) {
        try {
            validateReceiverHeights(source, receiver, heights);
            ADD_FAILURE() << "accepted: " << expect;
        } catch (const Error& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(expect), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
        EXPECT_THROW(caster.sample(source, receiver, {.heights = &heights}), Error) << expect;
        HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
        EXPECT_THROW(caster.sampleUnblocked(source, receiver, map, {.heights = &heights}), Error) << expect;
        for (const CpuStrategy strategy : {CpuStrategy::Auto, CpuStrategy::Bitmask, CpuStrategy::RayCast})
            EXPECT_THROW(sampler.sample(source, receiver, {.strategy = strategy, .heights = &heights}), Error) << expect;
    };
    const int count = receiver.sampleCount();
    refusedEverywhere(ReceiverHeights{std::vector<double>(std::size_t(count - 1), 0.1)}, "29 values");
    refusedEverywhere(ReceiverHeights{std::vector<double>(std::size_t(count + 1), 0.0)}, "31 values");
    ReceiverHeights bad{std::vector<double>(std::size_t(count), 0.2)};
    bad.metres[7] = std::numeric_limits<double>::quiet_NaN();
    refusedEverywhere(bad, "sample 7 (a 2, b 1) is not a finite number");
    bad.metres[7] = std::numeric_limits<double>::infinity();
    refusedEverywhere(bad, "not a finite number");
    bad.metres[7] = 3.0;   // exactly on the source plane
    refusedEverywhere(bad, "reaches the source's plane; keep it below 3");
    bad.metres[7] = 4.5;   // through it
    refusedEverywhere(bad, "reaches the source's plane");

    // Just short of the source, and far behind the receiver, are valid.
    bad.metres[7] = 2.99;
    bad.metres[8] = -20.0;
    EXPECT_NO_THROW(validateReceiverHeights(source, receiver, bad));
    EXPECT_NO_THROW(validateReceiverHeights(source, receiver, ReceiverHeights{}));
    const HiddenSampleMap wall = sampler.sample(source, receiver, {.strategy = CpuStrategy::Bitmask, .heights = &bad});
    EXPECT_EQ(wall.blockedCount(7), 0) << "the bump in front of the wall sees the whole source";
    EXPECT_EQ(wall.blockedCount(), wall.rayCount() - std::uint64_t(source.sampleCount()));
    EXPECT_EQ(wall, caster.sample(source, receiver, {.heights = &bad}));
}

TEST(ReceiverHeights, ZeroHeightsGiveExactlyTheFlatMap)
{
    for (unsigned seed = 1; seed <= 6; ++seed) {
        const RandomCase c = bumpyCase(seed);
        if (!c.valid())
            continue;
        const ReceiverHeights zero{std::vector<double>(std::size_t(c.receiver.sampleCount()), 0.0)};
        const RayCastScene caster(c.scene);
        EXPECT_EQ(caster.sample(c.source, c.receiver, {.heights = &zero}), caster.sample(c.source, c.receiver));
        const CpuBitmaskSampler sampler(c.scene);
        for (const bool simd : {true, false})
            for (const CpuStrategy strategy : {CpuStrategy::Auto, CpuStrategy::Bitmask, CpuStrategy::Hybrid}) {
                BitmaskOptions flat{.strategy = strategy, .smallCells = 4.0, .simd = simd};
                BitmaskOptions zeroed = flat;
                zeroed.heights = &zero;
                EXPECT_EQ(sampler.sample(c.source, c.receiver, zeroed), sampler.sample(c.source, c.receiver, flat))
                    << "seed " << seed << ", strategy " << int(strategy);
            }
    }
}

TEST(ReceiverHeights, WallWithAHoleHidesAllButTheBumpsRisingThroughIt)
{
    // Source at z = 0, receiver at z = 4 facing it (its normal toward the source is -z), a wall
    // at z = 3 wider than the shaft with a square hole. A sample raised by h lies at z = 4 - h:
    // above the wall (h > 1) it sees the whole source; below it, exactly the source samples whose
    // segment crosses z = 3 inside the hole.
    const float lo = 0.2371f, hi = 0.7713f;   // hole [lo, hi]^2, off every sample's rational grid
    const Scene scene = sceneOf({rectangle(-50, lo, -50, 50, 3), rectangle(hi, 50, -50, 50, 3),
                                 rectangle(lo, hi, -50, lo, 3), rectangle(lo, hi, hi, 50, 3)});
    const Patch source = xyPatch(0, 9, 7), receiver = xyPatch(4, 14, 12);
    ReceiverHeights heights;
    const double choices[] = {-0.61, 0.0, 0.37, 0.93, 1.13, 1.71, 2.47};
    for (int j = 0; j < receiver.sampleCount(); ++j)
        heights.metres.push_back(choices[(j * 5 + j / 7) % 7]);
    const RayCastScene caster(scene);
    const CpuBitmaskSampler sampler(scene);
    std::vector<std::pair<std::string, HiddenSampleMap>> maps;
    maps.emplace_back("embree", caster.sample(source, receiver, {.heights = &heights}));
    for (const bool simd : {true, false})
        for (const bool narrow : {true, false})
            maps.emplace_back(std::string(simd ? "simd" : "scalar") + (narrow ? ", narrowed" : ""),
                              sampler.sample(source, receiver,
                                             {.strategy = CpuStrategy::Bitmask, .narrowShaft = narrow, .simd = simd,
                                              .heights = &heights}));
    std::uint64_t visibleAboveWall = 0, throughHole = 0, blocked = 0;
    for (const auto& [name, map] : maps) {
        std::uint64_t wrong = 0;
        for (int j = 0; j < receiver.sampleCount(); ++j) {
            const glm::dvec3 p = displacedReceiverSample(source, receiver, heights, j);
            for (int i = 0; i < source.sampleCount(); ++i) {
                const glm::dvec3 s = source.sample(i);
                bool expected = false;
                if (p.z > 3.0) {
                    const glm::dvec3 q = s + (p - s) * (3.0 / p.z);
                    expected = !(q.x > lo && q.x < hi && q.y > lo && q.y < hi);
                    throughHole += !expected && name == "embree";
                } else {
                    visibleAboveWall += name == "embree";
                }
                blocked += expected && name == "embree";
                wrong += map.blocked(j, i) != expected;
            }
        }
        EXPECT_EQ(wrong, 0u) << name;
    }
    EXPECT_GT(visibleAboveWall, 1000u);
    EXPECT_GT(throughHole, 500u);
    EXPECT_GT(blocked, 2000u);
}

TEST(ReceiverHeights, ConstantHeightIsTheTranslatedPatch)
{
    // Every sample raised by the same height: the flat receiver moved along its normal.
    for (unsigned seed = 1; seed <= 8; ++seed) {
        const RandomCase c = bumpyCase(seed);
        if (!c.valid())
            continue;
        const ReceiverHeights raised{std::vector<double>(std::size_t(c.receiver.sampleCount()), 0.45)};
        Patch moved = c.receiver;
        moved.corner += 0.45 * receiverNormalTowardSource(c.source, c.receiver);
        const CpuBitmaskSampler sampler(c.scene);
        const HiddenSampleMap expected = RayCastScene(c.scene).sample(c.source, moved);
        for (const bool simd : {true, false}) {
            const HiddenSampleMap map =
                sampler.sample(c.source, c.receiver, {.strategy = CpuStrategy::Bitmask, .simd = simd, .heights = &raised});
            EXPECT_LE(map.differenceCount(expected) * 10000, map.rayCount()) << "seed " << seed;
        }
    }
}

TEST(ReceiverHeights, BitmaskMatchesTheReferenceOnRandomScenes)
{
    // Non-parallel patches, random height fields up to a metre either way, triangles in the bump
    // range and crossing the receiver plane, a floor in the receiver plane. Every CPU strategy
    // and both kernels must give the brute force's answer outside grazing rays, and agree with
    // Embree but for a handful of rays.
    int checked = 0;
    std::uint64_t rays = 0, blocked = 0, changedByBumps = 0, differFromEmbree = 0, floatPairs = 0, pairs = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        const RandomCase c = bumpyCase(seed);
        if (!c.valid())
            continue;
        ++checked;
        const ReceiverHeights heights = randomHeights(seed, c.receiver, -0.8, 1.0);
        const BruteForceMap reference = bumpyBruteForce(worldTriangles(c.scene), c.source, c.receiver, heights);
        const HiddenSampleMap embree = RayCastScene(c.scene).sample(c.source, c.receiver, {.heights = &heights});
        EXPECT_EQ(mismatches(embree, reference), 0u) << "embree, seed " << seed;
        const CpuBitmaskSampler sampler(c.scene);
        BitmaskStats stats;
        const HiddenSampleMap map =
            sampler.sample(c.source, c.receiver, {.strategy = CpuStrategy::Bitmask, .heights = &heights}, &stats);
        EXPECT_EQ(mismatches(map, reference), 0u) << "simd, seed " << seed;
        floatPairs += stats.debug.floatPairs;
        pairs += stats.pairs;
        differFromEmbree += map.differenceCount(embree);
        const HiddenSampleMap scalar =
            sampler.sample(c.source, c.receiver, {.strategy = CpuStrategy::Bitmask, .simd = false, .heights = &heights});
        EXPECT_EQ(mismatches(scalar, reference), 0u) << "scalar, seed " << seed;
        differFromEmbree += scalar.differenceCount(embree);
        EXPECT_EQ(map, sampler.sample(c.source, c.receiver,
                                      {.strategy = CpuStrategy::Bitmask, .narrowShaft = false, .heights = &heights}))
            << "narrowing changed the answer, seed " << seed;
        BitmaskStats hybridStats;
        const HiddenSampleMap hybrid = sampler.sample(
            c.source, c.receiver, {.strategy = CpuStrategy::Hybrid, .smallCells = 4.0, .heights = &heights}, &hybridStats);
        EXPECT_EQ(mismatches(hybrid, reference), 0u) << "hybrid, seed " << seed;
        EXPECT_STREQ(hybridStats.strategy, "hybrid");
        changedByBumps += map.differenceCount(sampler.sample(c.source, c.receiver, {.strategy = CpuStrategy::Bitmask}));
        rays += map.rayCount();
        blocked += map.blockedCount();
    }
    EXPECT_GE(checked, 30);
    EXPECT_GT(blocked, rays / 10);
    EXPECT_GT(changedByBumps, rays / 20) << "the heights must matter";
    // Two maps per seed against Embree: rays grazing an edge within float rounding only.
    EXPECT_LE(differFromEmbree * 10000, 2 * rays);
    if (CpuBitmaskSampler::simdAvailable()) {
        EXPECT_GT(floatPairs, pairs / 4);   // well-conditioned occluders still take the float kernel
        EXPECT_LT(floatPairs, pairs);
    }
}

TEST(ReceiverHeights, JitteredBumpyReceiverMatchesTheReference)
{
    const SourceJitter jitter{.seed = 4242};
    int checked = 0;
    for (unsigned seed = 41; seed <= 60; ++seed) {
        const RandomCase c = bumpyCase(seed);
        if (!c.valid())
            continue;
        ++checked;
        const ReceiverHeights heights = randomHeights(seed, c.receiver, -0.6, 1.2);
        const BruteForceMap reference = bumpyBruteForce(worldTriangles(c.scene), c.source, c.receiver, heights, jitter);
        const HiddenSampleMap embree =
            RayCastScene(c.scene).sample(c.source, c.receiver, {.jitter = jitter, .heights = &heights});
        EXPECT_EQ(mismatches(embree, reference), 0u) << "embree, seed " << seed;
        const CpuBitmaskSampler sampler(c.scene);
        for (const bool simd : {true, false})
            for (const CpuStrategy strategy : {CpuStrategy::Bitmask, CpuStrategy::Hybrid, CpuStrategy::RayCast}) {
                const HiddenSampleMap map = sampler.sample(
                    c.source, c.receiver,
                    {.strategy = strategy, .smallCells = 4.0, .simd = simd, .jitter = jitter, .heights = &heights});
                EXPECT_EQ(mismatches(map, reference), 0u)
                    << "seed " << seed << ", strategy " << int(strategy) << (simd ? ", simd" : ", scalar");
                EXPECT_LE(map.differenceCount(embree) * 10000, map.rayCount());
            }
    }
    EXPECT_GE(checked, 15);
}

TEST(ReceiverHeights, AutoAndRayCastStrategiesHonourHeights)
{
    // The comb of many small triangles (combWall) at z ~ 1, the receiver at z = 2, one source
    // sample and 1,024: Auto's choice, and each strategy forced. Samples raised above the comb
    // (h > 1.04) see everything; the rest see through its gaps.
    const Scene scene = sceneOf({combWall()});
    const CpuBitmaskSampler sampler(scene);
    const RayCastScene reference(scene);
    const Patch receiver = xyPatch(2, 32, 32);
    const ReceiverHeights heights = randomHeights(3, receiver, -0.5, 1.5);
    for (const Patch& source : {xyPatch(0, 1, 1), xyPatch(0, 32, 32)}) {
        const HiddenSampleMap expected = reference.sample(source, receiver, {.heights = &heights});
        EXPECT_GT(expected.differenceCount(reference.sample(source, receiver)), expected.rayCount() / 20);
        for (int j = 0; j < receiver.sampleCount(); ++j)
            if (heights.metres[std::size_t(j)] > 1.05) {
                EXPECT_EQ(expected.blockedCount(j), 0) << "sample " << j << " above the comb";
            }
        BitmaskStats stats;
        const HiddenSampleMap automatic = sampler.sample(source, receiver, {.heights = &heights}, &stats);
        if (std::string(stats.strategy) == "raycast") {
            EXPECT_EQ(automatic, expected);
        } else {
            EXPECT_LE(automatic.differenceCount(expected) * 10000, automatic.rayCount()) << stats.strategy;
        }
        EXPECT_LE(sampler.sample(source, receiver, {.strategy = CpuStrategy::Bitmask, .heights = &heights})
                          .differenceCount(expected) *
                      10000,
                  expected.rayCount());
        EXPECT_EQ(sampler.sample(source, receiver, {.strategy = CpuStrategy::RayCast, .heights = &heights}), expected);
    }
}

TEST(ReceiverHeights, NoWatertightCullingWhenBumpsRiseIntoAClosedMesh)
{
    // A closed box at z in about [1.22, 1.81] over the receiver's middle; the flat receiver (z = 2) is
    // apart from it, but the bumps under it rise to z = 1.5, inside. Their rays leave the box
    // through its face toward the source, a front face: culling it would unblock them.
    Scene scene;
    const std::uint32_t box = scene.addMesh(closedBox());
    glm::mat4 m(1.0f);
    m[0][0] = m[1][1] = 0.4871f;   // off the samples' rational grid: no grazing rays
    m[2][2] = 0.5923f;
    m[3] = glm::vec4(0.5013f, 0.4987f, 1.5117f, 1.0f);
    scene.instances.push_back({"box", box, m});
    const Patch source = xyPatch(0, 8, 8), receiver = xyPatch(2, 16, 16);
    ReceiverHeights heights;
    int inside = 0;
    for (int j = 0; j < receiver.sampleCount(); ++j) {
        const glm::dvec3 p = receiver.sample(j);
        const bool under = std::abs(p.x - 0.5) < 0.2 && std::abs(p.y - 0.5) < 0.2;
        heights.metres.push_back(under ? 0.5 : 0.05);
        inside += under;
    }
    ASSERT_GT(inside, 0);
    const CpuBitmaskSampler sampler(scene);
    const BruteForceMap reference = bumpyBruteForce(worldTriangles(scene), source, receiver, heights);
    const HiddenSampleMap expected = RayCastScene(scene).sample(source, receiver, {.heights = &heights});
    EXPECT_EQ(mismatches(expected, reference), 0u);
    for (const bool simd : {true, false}) {
        const HiddenSampleMap map =
            sampler.sample(source, receiver, {.strategy = CpuStrategy::Bitmask, .simd = simd, .heights = &heights});
        EXPECT_EQ(mismatches(map, reference), 0u) << (simd ? "simd" : "scalar");
        EXPECT_EQ(map, sampler.sample(source, receiver,
                                      {.strategy = CpuStrategy::Bitmask, .watertightCulling = false, .simd = simd,
                                       .heights = &heights}));
        for (int j = 0; j < receiver.sampleCount(); ++j)
            if (heights.metres[std::size_t(j)] == 0.5) {
                EXPECT_EQ(map.blockedCount(j), source.sampleCount()) << "sample " << j << " inside the box";
            }
    }
}
