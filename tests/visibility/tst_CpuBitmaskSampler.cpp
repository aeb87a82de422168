// The exact CPU bitmask sampler against closed forms, the brute-force caster and the Embree reference.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "BruteForceCaster.h"
#include "ExactJudge.h"
#include "TestScenes.h"
#include "bitmask/Strategy.h"
#include "bitmask/TilePass.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/RayCastSampler.h"
#include "visibility/ReceiverHeights.h"

using namespace sightline;
using namespace sightline::test;

TEST(CpuBitmaskSampler, EmptySceneAndFullWall)
{
    EXPECT_EQ(CpuBitmaskSampler(Scene{}).sample(xyPatch(0, 32, 32), xyPatch(2, 32, 32)).blockedCount(), 0u);
    const Scene wall = sceneOf({quad({-10, -10, 1}, {20, 0, 0}, {0, 20, 0})});
    const HiddenSampleMap map = CpuBitmaskSampler(wall).sample(xyPatch(0, 32, 32), xyPatch(2, 32, 32));
    EXPECT_EQ(map.blockedCount(), map.rayCount());
}

TEST(CpuBitmaskSampler, NoCrackAlongTheSharedEdgeOfAWall)
{
    // A 10 m wall of two triangles, tilted by float rounding (what glm::rotate by 90 degrees
    // gives), with both patches centred on its diagonal: hundreds of rays pass exactly through
    // the shared edge. The single-precision kernel once let 2,736 of 65,536 through (found by the
    // editor's screenshot test); both triangles must claim such rays, as Embree does.
    Mesh plane;   // the editor's built-in plane, placed by that rotation and scaled by 10
    const glm::vec3 column0(-4.37114e-07f, 10.0f, 0.0f), column2(0.0f, 0.0f, 9.999999046325684f), origin(3.0f, 1.5f, 0.0f);
    for (const auto& [x, z] : {std::pair{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}})
        plane.positions.push_back(origin + x * column0 + z * column2);
    plane.indices = {0, 2, 1, 0, 3, 2};
    const Scene wall = sceneOf({plane});
    Patch source, receiver;   // 1 m squares at x = 0 and x = 6, centred on the wall's diagonal
    source.corner = {0.0, 1.0, 0.5};
    source.u = {0.0, 0.0, -1.0};
    source.v = {0.0, 1.0, 0.0};
    receiver.corner = {6.0, 1.0, -0.5};
    receiver.u = {0.0, 0.0, 1.0};
    receiver.v = {0.0, 1.0, 0.0};
    source.na = source.nb = receiver.na = receiver.nb = 16;
    for (bool simd : {true, false}) {
        BitmaskOptions options;
        options.simd = simd;
        const HiddenSampleMap map = CpuBitmaskSampler(wall).sample(source, receiver, options);
        EXPECT_EQ(map.blockedCount(), map.rayCount()) << (simd ? "SIMD" : "double");
    }
}

TEST(CpuBitmaskSampler, HalfPlaneMatchesTheFormula)
{
    const double edge = 0.437;
    const Scene scene = sceneOf({quad({-50, -50, 1}, {50 + float(edge), 0, 0}, {0, 100, 0})});
    const Patch source = xyPatch(0, 13, 7), receiver = xyPatch(3, 52, 9);
    const HiddenSampleMap map = CpuBitmaskSampler(scene).sample(source, receiver);
    std::uint64_t mismatches = 0, expected = 0;
    for (int j = 0; j < receiver.sampleCount(); ++j)
        for (int i = 0; i < source.sampleCount(); ++i) {
            const double x = source.sample(i).x + (receiver.sample(j).x - source.sample(i).x) / 3.0;
            expected += x < edge;
            mismatches += (x < edge) != map.blocked(j, i);
        }
    EXPECT_GT(expected, 0u);
    EXPECT_EQ(mismatches, 0u);
}

TEST(CpuBitmaskSampler, SurfacesAtTheSegmentEndsDoNotBlock)
{
    const Scene scene = sceneOf({quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0}), quad({-5, -5, 2}, {10, 0, 0}, {0, 10, 0})});
    EXPECT_EQ(CpuBitmaskSampler(scene).sample(xyPatch(0, 8, 8), xyPatch(2, 8, 8)).blockedCount(), 0u);
}

TEST(CpuBitmaskSampler, AgreesWithBruteForceOnRandomScenes)
{
    // Non-parallel patches, grids from 1x1 to 12x12, tiny, medium and huge triangles, triangles
    // crossing both patch planes.
    int checked = 0;
    std::uint64_t rays = 0, blocked = 0, smallTriangles = 0, floatPairs = 0, pairs = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        const RandomCase c = randomCase(seed);
        if (!c.valid())
            continue;   // the generator made an invalid pair; refusal is tested separately
        ++checked;
        const BruteForceMap reference = bruteForceSample(worldTriangles(c.scene), c.source, c.receiver);
        const CpuBitmaskSampler sampler(c.scene);
        BitmaskStats bitmaskStats;
        const HiddenSampleMap map = sampler.sample(c.source, c.receiver, {.strategy = CpuStrategy::Bitmask}, &bitmaskStats);
        EXPECT_EQ(mismatchesOutsideGrazing(map, reference), 0u)
            << "seed " << seed << ": " << map.blockedCount() << " vs " << reference.blocked.blockedCount();
        floatPairs += bitmaskStats.debug.floatPairs;
        pairs += bitmaskStats.pairs;
        // Double precision everywhere (the path for CPUs without AVX2).
        const HiddenSampleMap scalar = sampler.sample(c.source, c.receiver, {.strategy = CpuStrategy::Bitmask, .simd = false});
        EXPECT_EQ(mismatchesOutsideGrazing(scalar, reference), 0u) << "scalar, seed " << seed;
        // Hybrid with a threshold that sends the tiny and some medium triangles to ray casting.
        BitmaskStats stats;
        const HiddenSampleMap hybrid =
            sampler.sample(c.source, c.receiver, {.strategy = CpuStrategy::Hybrid, .smallCells = 4.0}, &stats);
        EXPECT_EQ(mismatchesOutsideGrazing(hybrid, reference), 0u) << "hybrid, seed " << seed;
        EXPECT_STREQ(stats.strategy, "hybrid");
        EXPECT_EQ(map, sampler.sample(c.source, c.receiver, {.strategy = CpuStrategy::Bitmask, .narrowShaft = false}))
            << "narrowing changed the answer, seed " << seed;
        smallTriangles += stats.debug.smallTriangles;
        rays += map.rayCount();
        blocked += map.blockedCount();
    }
    EXPECT_GE(checked, 30);
    EXPECT_GT(blocked, rays / 10);
    EXPECT_GT(smallTriangles, 100u);   // the hybrid's ray pass was exercised
    if (CpuBitmaskSampler::simdAvailable()) {
        // Both kernels were exercised: well-conditioned occluders by SIMD, the rest in double.
        EXPECT_GT(floatPairs, pairs / 4);
        EXPECT_LT(floatPairs, pairs);
    }
}

TEST(CpuBitmaskSampler, MatchesTheReferenceAcrossSampleCounts)
{
    // A soup in the shaft; source grids of 1, 32, 128 (16x8), 544 (32x17: rows paired into
    // words, one left over), 1024 (32x32, 64x16) samples and receivers up to 512x512, some not a
    // multiple of the 8x8 tiles; threads 1 and all give the same bits.
    const Mesh soup = randomSoup(11, 400, -0.3f, 1.3f, 0.3f, 1.7f, 0.15f);
    const Scene scene = sceneOf({soup});
    const RayCastScene reference(scene);
    const CpuBitmaskSampler sampler(scene);
    struct Grid { int na, nb, rna, rnb; };
    for (const Grid g : {Grid{1, 1, 64, 64}, Grid{32, 1, 32, 32}, Grid{16, 8, 40, 24}, Grid{32, 17, 37, 19},
                         Grid{32, 32, 32, 32}, Grid{64, 16, 16, 16}, Grid{4, 4, 512, 512}}) {
        const Patch source = xyPatch(0, g.na, g.nb), receiver = xyPatch(2, g.rna, g.rnb);
        const HiddenSampleMap expected = reference.sample(source, receiver);
        const HiddenSampleMap map = sampler.sample(source, receiver, {.strategy = CpuStrategy::Bitmask});
        const std::uint64_t differ = map.differenceCount(expected);
        // Exact up to grazing rays: at most 1 in 10^4 (the bar), and in practice ~0.
        EXPECT_LE(differ * 10000, map.rayCount()) << g.na << "x" << g.nb << " / " << g.rna << "x" << g.rnb;
        EXPECT_GT(expected.blockedCount(), 0u);
        EXPECT_EQ(map, sampler.sample(source, receiver, {.threads = 1, .strategy = CpuStrategy::Bitmask}));
        // Parallel patches: the narrowing test's single-precision bounds use shared factors.
        EXPECT_EQ(map, sampler.sample(source, receiver, {.strategy = CpuStrategy::Bitmask, .narrowShaft = false}))
            << "narrowing changed the answer, " << g.na << "x" << g.nb << " / " << g.rna << "x" << g.rnb;
        const HiddenSampleMap hybrid = sampler.sample(source, receiver, {.strategy = CpuStrategy::Hybrid, .smallCells = 6.0});
        EXPECT_LE(hybrid.differenceCount(expected) * 10000, map.rayCount()) << "hybrid " << g.na << "x" << g.nb;
    }
}

TEST(CpuBitmaskSampler, RefusesInvalidInput)
{
    const CpuBitmaskSampler sampler(Scene{});
    EXPECT_THROW(sampler.sample(xyPatch(0, 0, 8), xyPatch(2, 8, 8)), Error);
    EXPECT_THROW(sampler.sample(xyPatch(0, 50, 40), xyPatch(2, 8, 8)), Error);
    EXPECT_THROW(sampler.sample(xyPatch(0, 8, 8), xyPatch(2, 0, 0)), Error);
    EXPECT_THROW(sampler.sample(xyPatch(0, 8, 8), xyPatch(0, 8, 8)), Error);
}

namespace {

/// Closed boxes scattered in the shaft (some placed by mirroring transforms), plus a flat quad.
Scene boxesInTheShaft(unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> xy(-0.2f, 1.2f), z(0.4f, 1.6f), size(0.05f, 0.4f), sign(-1.0f, 1.0f);
    Scene scene;
    const std::uint32_t box = scene.addMesh(closedBox());
    for (int i = 0; i < 40; ++i) {
        glm::mat4 m(1.0f);
        m[0][0] = size(rng) * (sign(rng) < 0 ? -1.0f : 1.0f);   // some mirrored
        m[1][1] = size(rng);
        m[2][2] = size(rng);
        m[1][0] = 0.3f * sign(rng);                               // and sheared
        m[3] = glm::vec4(xy(rng), xy(rng), z(rng), 1.0f);
        scene.instances.push_back({"box", box, m});
    }
    scene.addMeshInstance(quad({0.1f, 0.2f, 1.1f}, {0.3f, 0, 0}, {0, 0.2f, 0.05f}));
    return scene;
}

} // namespace

TEST(CpuBitmaskSampler, WatertightCullingNeverChangesTheAnswer)
{
    for (unsigned seed = 1; seed <= 5; ++seed) {
        const Scene scene = boxesInTheShaft(seed);
        const Patch source = xyPatch(0, 16, 16), receiver = xyPatch(2, 24, 24);
        const CpuBitmaskSampler sampler(scene);
        BitmaskStats culledStats, plainStats;
        const HiddenSampleMap culled = sampler.sample(source, receiver, {.strategy = CpuStrategy::Bitmask}, &culledStats);
        const HiddenSampleMap plain = sampler.sample(
            source, receiver, {.strategy = CpuStrategy::Bitmask, .watertightCulling = false}, &plainStats);
        EXPECT_EQ(culled, plain) << "seed " << seed;
        // Each box lies wholly in front of the source, so at least its face towards the source
        // (2 triangles) faces all four source corners; boxes wholly outside the shaft's hull are
        // dropped before culling (about a quarter here).
        EXPECT_GE(culledStats.debug.culledFrontFaces, 40u) << "seed " << seed;
        EXPECT_EQ(plainStats.debug.culledFrontFaces, 0u);
        EXPECT_LT(culledStats.pairs, plainStats.pairs);
        const HiddenSampleMap reference = RayCastScene(scene).sample(source, receiver);
        EXPECT_LE(culled.differenceCount(reference) * 10000, culled.rayCount()) << "seed " << seed;
    }
}

TEST(CpuBitmaskSampler, ObjectsStandingOnAFloorMatchTheReference)
{
    // A floor seen from a wall patch across a room (the demo's conservatory floor): boxes stand on
    // it, so each touches its own influence region and needs per-sample clipping where it stands,
    // but the samples beyond it are far and well conditioned. Each tile takes the path its own
    // samples need, and the answer is the reference's.
    Scene scene;
    const std::uint32_t box = scene.addMesh(closedBox());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> x(3.0f, 9.0f), y(-2.5f, 2.5f), size(0.3f, 1.2f);
    for (int i = 0; i < 12; ++i) {
        glm::mat4 m(1.0f);
        m[0][0] = size(rng), m[1][1] = size(rng), m[2][2] = size(rng);
        m[3] = glm::vec4(x(rng), y(rng), 0.5f * m[2][2], 1.0f);   // standing on z = 0
        scene.instances.push_back({"box", box, m});
    }
    Patch source;
    source.corner = {0.0, -1.0, 1.0};   // a 2 x 2 m wall patch at x = 0, 1 to 3 m up
    source.u = {0.0, 2.0, 0.0};
    source.v = {0.0, 0.0, 2.0};
    source.na = source.nb = 32;
    const RayCastScene reference(scene);
    const CpuBitmaskSampler sampler(scene);
    // 8 x 6 m of floor, its rows running away from the source (each sample at its own distance)
    // or along it (a row at one distance, where one clip serves the whole row).
    for (const bool rowsAlongTheSource : {false, true}) {
        Patch floor;   // normal up either way
        floor.corner = rowsAlongTheSource ? glm::dvec3(2.0, 3.0, 0.0) : glm::dvec3(2.0, -3.0, 0.0);
        floor.u = rowsAlongTheSource ? glm::dvec3(0.0, -6.0, 0.0) : glm::dvec3(8.0, 0.0, 0.0);
        floor.v = rowsAlongTheSource ? glm::dvec3(8.0, 0.0, 0.0) : glm::dvec3(0.0, 6.0, 0.0);
        floor.na = floor.nb = 64;
        const HiddenSampleMap expected = reference.sample(source, floor);
        BitmaskStats stats;
        const HiddenSampleMap map = sampler.sample(source, floor, {.strategy = CpuStrategy::Bitmask}, &stats);
        EXPECT_GT(expected.blockedCount(), expected.rayCount() / 10);
        EXPECT_LT(expected.blockedCount(), expected.rayCount() / 2);
        EXPECT_LE(map.differenceCount(expected) * 10000, map.rayCount()) << rowsAlongTheSource;
        EXPECT_EQ(map, sampler.sample(source, floor, {.strategy = CpuStrategy::Bitmask, .narrowShaft = false}));
        const HiddenSampleMap scalar = sampler.sample(source, floor, {.strategy = CpuStrategy::Bitmask, .simd = false});
        EXPECT_LE(scalar.differenceCount(expected) * 10000, map.rayCount()) << rowsAlongTheSource;
        if (CpuBitmaskSampler::simdAvailable()) {
            // Every box touches the floor: over its whole region it needs clipping, so the float
            // kernel runs only where a tile's own samples allow it (0 when the path was chosen
            // per occluder).
            EXPECT_GT(stats.debug.floatPairs, stats.pairs / 4) << stats.debug.floatPairs << " of " << stats.pairs;
        }
    }
}

TEST(CpuBitmaskSampler, NoCullingForAReceiverInsideAClosedMesh)
{
    // The receiver sits inside a closed box: its rays leave through back faces only, so the front
    // faces (seen from the source) are the ones that block. Culling them would unblock every ray.
    Scene scene;
    const std::uint32_t box = scene.addMesh(closedBox());
    glm::mat4 m(1.0f);
    m[0][0] = m[1][1] = 3.0f;
    m[2][2] = 1.0f;
    m[3] = glm::vec4(0.5f, 0.5f, 2.0f, 1.0f);   // z in [1.5, 2.5], receiver at z = 2 inside
    scene.instances.push_back({"room", box, m});
    const HiddenSampleMap map = CpuBitmaskSampler(scene).sample(xyPatch(0, 8, 8), xyPatch(2, 8, 8));
    EXPECT_EQ(map.blockedCount(), map.rayCount());
}

TEST(CpuBitmaskSampler, AutoFollowsItsCostModel)
{
    // A comb of 14,400 small triangles fills the shaft: every triangle touches most receiver
    // samples, so with few source samples the bitmask's pairs outnumber the rays. Where one
    // method's predicted cost is under half the other's, Auto takes it without timing; in between
    // it times both on a few tiles (bitmask/Strategy.h). Every answer is the reference's. (The
    // patches keep their roles here: AutoTakesTheBitmaskWithSwappedRolesByItsOwnRule.)
    const Scene scene = sceneOf({combWall(120)});
    const CpuBitmaskSampler sampler(scene);
    const RayCastScene reference(scene);
    BitmaskOptions options;
    options.swapRoles = false;
    int clearBitmask = 0, clearRays = 0, probed = 0;
    for (int r : {32, 64})
        for (int side : {32, 8, 4, 2, 1}) {
            const Patch source = xyPatch(0, side, side), receiver = xyPatch(2, r, r);
            BitmaskStats stats;
            const HiddenSampleMap map = sampler.sample(source, receiver, options, &stats);
            EXPECT_FALSE(stats.swappedRoles);
            const double ratio = stats.debug.predictedBitmaskMs / stats.debug.predictedRayMs;
            if (ratio <= 0.5) {
                EXPECT_STREQ(stats.strategy, "bitmask") << side << " " << r;
                EXPECT_FALSE(stats.debug.probed);
                ++clearBitmask;
            } else if (ratio >= 2.0) {
                EXPECT_STREQ(stats.strategy, "raycast") << side << " " << r;
                EXPECT_FALSE(stats.debug.probed);
                ++clearRays;
            } else {
                EXPECT_TRUE(stats.debug.probed) << side << " " << r << ": ratio " << ratio;
                ++probed;
            }
            const HiddenSampleMap expected = reference.sample(source, receiver);
            const ExactJudge judge(worldTriangles(scene), source, receiver);
            EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 256, 1u)).nonTie(), 0u) << side << " " << r;
        }
    EXPECT_GT(clearBitmask, 0);
    EXPECT_GT(probed, 0);
    // 20,000 small triangles in the shaft and one source sample: the bitmask's setup alone costs
    // far more than the 1,024 rays, so Auto ray casts without timing.
    const Scene soup = sceneOf({randomSoup(3, 20000, -0.5f, 1.5f, 0.2f, 1.8f, 0.05f)});
    const Patch one = xyPatch(0, 1, 1), receiver = xyPatch(2, 32, 32);
    BitmaskStats stats;
    const HiddenSampleMap map = CpuBitmaskSampler(soup).sample(one, receiver, options, &stats);
    EXPECT_LE(stats.debug.predictedRayMs, 0.5 * stats.debug.predictedBitmaskMs);
    EXPECT_STREQ(stats.strategy, "raycast");
    EXPECT_FALSE(stats.debug.probed);
    ++clearRays;
    const HiddenSampleMap expected = RayCastScene(soup).sample(one, receiver);
    const ExactJudge judge(worldTriangles(soup), one, receiver);
    EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 256, 1u)).nonTie(), 0u);
}

TEST(CpuBitmaskSampler, AutoTakesTheBitmaskWithSwappedRolesByItsOwnRule)
{
    // Fewer source samples than receiver samples, at most 1024 of those: the patches swap roles.
    // Auto takes the bitmask where its prediction is no dearer than the rays', rays where it is
    // far dearer, and in between times the rays of an eighth of the (swapped) receiver samples,
    // then, unless those are clearly cheaper, the bitmask's whole call (bitmask/Strategy.h). The
    // comb and a soup of 20,000 triangles at 1-16x16 source samples give all three. Every answer
    // is exact, whichever method gave it.
    const Scene comb = sceneOf({combWall(120)});
    const Scene soup = sceneOf({randomSoup(3, 20000, -0.5f, 1.5f, 0.2f, 1.8f, 0.05f)});
    int byBitmask = 0, byRays = 0, timed = 0;
    for (const Scene* scene : {&comb, &soup})
        for (int side : {16, 8, 4, 2, 1}) {
            const CpuBitmaskSampler sampler(*scene);
            const Patch source = xyPatch(0, side, side), receiver = xyPatch(2, 32, 32);
            BitmaskStats stats;
            const HiddenSampleMap map = sampler.sample(source, receiver, {}, &stats);
            EXPECT_TRUE(stats.swappedRoles) << side;
            const double ratio = stats.debug.predictedBitmaskMs / stats.debug.predictedRayMs;
            if (ratio <= bitmask::kSwappedBitmaskClearCut) {
                EXPECT_STREQ(stats.strategy, "bitmask") << side;
                EXPECT_FALSE(stats.debug.probed) << side;
                ++byBitmask;
            } else if (ratio >= bitmask::kSwappedRaysClearCut) {
                EXPECT_STREQ(stats.strategy, "raycast") << side;
                EXPECT_FALSE(stats.debug.probed) << side;
                ++byRays;
            } else {
                EXPECT_TRUE(stats.debug.probed) << side << ": ratio " << ratio;
                ++timed;
            }
            EXPECT_EQ(map.sourceCount(), source.sampleCount());
            EXPECT_EQ(map.receiverCount(), receiver.sampleCount());
            const HiddenSampleMap expected = RayCastScene(*scene).sample(source, receiver);
            const ExactJudge judge(worldTriangles(*scene), source, receiver);
            EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 4096, 1u)).nonTie(), 0u) << side;
        }
    EXPECT_GT(byBitmask, 0);
    EXPECT_GT(byRays, 0);
    EXPECT_GT(timed, 0);
}

namespace {

/// Samples the pair with the patches' roles swapped where BitmaskOptions allows and with them
/// kept; expects the two maps to agree but for ties (judged by the exact brute force) and
/// returns the swapped call's stats.
BitmaskStats expectSwapChangesOnlyTies(const Scene& scene, const CpuBitmaskSampler& sampler, const Patch& source,
                                       const Patch& receiver, CpuStrategy strategy)
{
    BitmaskOptions swapped, kept;
    swapped.strategy = kept.strategy = strategy;
    kept.swapRoles = false;
    BitmaskStats swappedStats, keptStats;
    const HiddenSampleMap a = sampler.sample(source, receiver, swapped, &swappedStats);
    const HiddenSampleMap b = sampler.sample(source, receiver, kept, &keptStats);
    EXPECT_FALSE(keptStats.swappedRoles);
    EXPECT_EQ(keptStats.receiverTiles, 1);
    EXPECT_EQ(a.sourceCount(), source.sampleCount());
    EXPECT_EQ(a.receiverNa(), receiver.na);
    EXPECT_EQ(a.receiverNb(), receiver.nb);
    const ExactJudge judge(worldTriangles(scene), source, receiver);
    EXPECT_EQ(judge.judge(a, raysToJudge({&a, &b}, 8192, 1u)).nonTie(), 0u);
    EXPECT_GT(a.blockedCount(), a.rayCount() / 10);
    EXPECT_LT(a.differenceCount(b), a.rayCount() / 1000);
    return swappedStats;
}

} // namespace

TEST(CpuBitmaskSampler, PatchesSwapRolesOnlyWhereTheAnswerCannotChange)
{
    // The same rays either way round (docs/design.md §2's test does not tell a segment's ends apart):
    // the swapped map, transposed back, agrees with the unswapped one but for ties, on a comb
    // and on random triangles. Jitter (a per-receiver shift of the source grid), heights (a
    // bumpy receiver), table mode and a forced ray cast (the reference's answer, bit for bit)
    // keep the roles; so do receivers of up to kMaxSourceSamples in more than 32 columns (past
    // kMaxSourceSamples they swap in tiles: ReceiversPastASourcesSamplesAreSampledInSwappedTiles).
    const Scene scene = sceneOf({combWall(40), randomSoup(7, 400, -0.5f, 1.5f, 0.2f, 1.8f, 0.2f)});
    const CpuBitmaskSampler sampler(scene);
    const Patch source = xyPatch(0, 16, 8), receiver = xyPatch(2, 32, 32);
    for (CpuStrategy strategy : {CpuStrategy::Auto, CpuStrategy::Bitmask, CpuStrategy::Hybrid}) {
        const BitmaskStats stats = expectSwapChangesOnlyTies(scene, sampler, source, receiver, strategy);
        EXPECT_TRUE(stats.swappedRoles);
        EXPECT_EQ(stats.receiverTiles, 1);
    }
    const auto swaps = [&](const Patch& s, const Patch& r, BitmaskOptions options) {
        BitmaskStats stats;
        sampler.sample(s, r, options, &stats);
        return stats.swappedRoles;
    };
    BitmaskOptions jittered;
    jittered.jitter.seed = 3;
    EXPECT_FALSE(swaps(source, receiver, jittered));
    BitmaskOptions forced;
    forced.strategy = CpuStrategy::RayCast;
    EXPECT_FALSE(swaps(source, receiver, forced));
    BitmaskOptions table;
    table.mode = MaskMode::Table;
    EXPECT_FALSE(swaps(source, receiver, table));
    ReceiverHeights heights;
    heights.metres.assign(std::size_t(receiver.sampleCount()), 0.0);
    heights.metres[5] = 0.1;
    BitmaskOptions bumpy;
    bumpy.heights = &heights;
    EXPECT_FALSE(swaps(source, receiver, bumpy));
    EXPECT_TRUE(swaps(source, xyPatch(2, 64, 32), {}));    // 2048 receiver samples: in two tiles
    EXPECT_FALSE(swaps(source, xyPatch(2, 64, 8), {}));    // 64 columns
    EXPECT_FALSE(swaps(xyPatch(0, 32, 32), receiver, {})); // as many samples either way
    EXPECT_TRUE(swaps(source, xyPatch(2, 32, 8), {}));
}

TEST(CpuBitmaskSampler, ReceiversPastASourcesSamplesAreSampledInSwappedTiles)
{
    // A 70x45 receiver (3,150 samples: past a source's 1,024) against a 16x8 source: split into
    // 3 x 2 tiles of 23-24 x 22-23 samples, each swapped; the map put together agrees with the
    // whole receiver's, sampled unswapped, but for ties, and with the exact brute force.
    const Scene scene = sceneOf({combWall(40), randomSoup(7, 400, -0.5f, 1.5f, 0.2f, 1.8f, 0.2f)});
    const CpuBitmaskSampler sampler(scene);
    const Patch source = xyPatch(0, 16, 8), receiver = xyPatch(2, 70, 45);
    for (CpuStrategy strategy : {CpuStrategy::Auto, CpuStrategy::Bitmask}) {
        const BitmaskStats stats = expectSwapChangesOnlyTies(scene, sampler, source, receiver, strategy);
        EXPECT_TRUE(stats.swappedRoles);
        EXPECT_EQ(stats.receiverTiles, 6);
    }
}

TEST(CpuBitmaskSampler, AutoReusesItsTimedChoiceOnSimilarConfigurations)
{
    // The comb at 64x64 receiver samples, with the source grid for which the predictions lie
    // closest to each other, well within the factor of two where Auto times both (found by
    // trying a few, so that the test does not depend on the model's constants). The next seven calls on a similar
    // configuration (the receiver moved a little) take that choice without timing; the eighth
    // times again, and so does a call after the receiver turned to face another way, or after
    // setScene. The first probe on a fresh sampler's grids is cold (Strategy.h, probeVerdict):
    // the next call times again, warm, and its choice is the one reused. Every answer is the
    // reference's. (The patches keep their roles, whole: swapped calls probe by rays alone.)
    const Scene scene = sceneOf({combWall(120)});
    BitmaskOptions keep;
    keep.swapRoles = false;
    const RayCastScene reference(scene);
    Patch receiver = xyPatch(2, 64, 64);
    BitmaskStats stats;
    int bestSide = 0;
    double bestGap = std::log(2.0);
    for (const int side : {1, 2, 3, 4, 6, 8, 12, 16, 24, 32}) {
        CpuBitmaskSampler(scene).sample(xyPatch(0, side, side), receiver, keep, &stats);
        const double gap = std::abs(std::log(stats.debug.predictedRayMs / stats.debug.predictedBitmaskMs));
        if (stats.debug.probed && gap < bestGap)
            bestSide = side, bestGap = gap;
    }
    ASSERT_GT(bestSide, 0) << "no source grid puts the comb in the probing band";
    Patch source = xyPatch(0, bestSide, bestSide);
    CpuBitmaskSampler sampler(scene);
    sampler.sample(source, receiver, keep, &stats);
    ASSERT_TRUE(stats.debug.probed);
    receiver.corner.x += 0.01;
    sampler.sample(source, receiver, keep, &stats);
    ASSERT_TRUE(stats.debug.probed) << "a cold probe's choice was reused";
    ASSERT_FALSE(stats.debug.reusedTimedChoice);
    // The choice for later calls may differ from the rest of this call's (its setup was paid).
    sampler.sample(source, receiver, keep, &stats);
    ASSERT_TRUE(stats.debug.reusedTimedChoice);
    const std::string chosen = stats.strategy;
    for (int call = 2; call <= 8; ++call) {
        receiver.corner.x += 0.01;   // a drag: similar
        const HiddenSampleMap map = sampler.sample(source, receiver, keep, &stats);
        EXPECT_EQ(stats.debug.probed, call == 8) << call;
        EXPECT_EQ(stats.debug.reusedTimedChoice, call < 8) << call;
        if (stats.debug.reusedTimedChoice) {
            EXPECT_EQ(chosen, stats.strategy) << call;
        }
        const HiddenSampleMap expected = reference.sample(source, receiver);
        const ExactJudge judge(worldTriangles(scene), source, receiver);
        EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 256, 1u)).nonTie(), 0u) << call;
    }
    // Turned by 30 degrees about its centre: not the configuration the choice was measured on.
    Patch turned = receiver;
    const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
    turned.u = {c, 0.0, s};
    turned.corner = receiver.centre() - 0.5 * (turned.u + turned.v);
    sampler.sample(source, turned, keep, &stats);
    EXPECT_FALSE(stats.debug.reusedTimedChoice);
    sampler.setScene(scene);
    sampler.sample(source, receiver, keep, &stats);
    EXPECT_FALSE(stats.debug.reusedTimedChoice);
}

TEST(CpuBitmaskSampler, AutoReusesAClearCutChoiceWithoutEstimatingAgain)
{
    // The comb at 32x32 receiver samples from 32x32 source samples: the bitmask, clear-cut by
    // the estimate. The next seven calls on a similar configuration take that choice without
    // estimating (the estimate prepares every 32nd triangle: milliseconds on a dense mesh); the
    // eighth estimates again, as does a call with the double kernel, whose costs differ. Every
    // answer is the reference's.
    const Scene scene = sceneOf({combWall(120)});
    const RayCastScene reference(scene);
    const CpuBitmaskSampler sampler(scene);
    const Patch source = xyPatch(0, 32, 32);
    Patch receiver = xyPatch(2, 32, 32);
    BitmaskStats stats;
    sampler.sample(source, receiver, {}, &stats);
    ASSERT_GT(stats.debug.estimatedPairs, 0u);
    ASSERT_FALSE(stats.debug.probed);
    ASSERT_FALSE(stats.debug.reusedChoice);
    const std::string chosen = stats.strategy;
    for (int call = 1; call <= 8; ++call) {
        receiver.corner.x += 0.01;
        const HiddenSampleMap map = sampler.sample(source, receiver, {}, &stats);
        EXPECT_EQ(stats.debug.reusedChoice, call < 8) << call;
        EXPECT_FALSE(stats.debug.reusedTimedChoice) << call;
        EXPECT_EQ(stats.debug.estimatedPairs > 0, call == 8) << call;
        EXPECT_EQ(chosen, stats.strategy) << call;
        const HiddenSampleMap expected = reference.sample(source, receiver);
        const ExactJudge judge(worldTriangles(scene), source, receiver);
        EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 256, 1u)).nonTie(), 0u) << call;
    }
    if (CpuBitmaskSampler::simdAvailable()) {   // else both calls take the double kernel
        sampler.sample(source, receiver, {.simd = false}, &stats);
        EXPECT_FALSE(stats.debug.reusedChoice);
        EXPECT_GT(stats.debug.estimatedPairs, 0u);
    }
}

TEST(RayCastSampler, UnblockedCastsOnlyTheReceiverSubset)
{
    const Scene wall = sceneOf({quad({-5, -5, 1}, {10, 0, 0}, {0, 10, 0})});
    const RayCastScene caster(wall);
    const Patch source = xyPatch(0, 4, 4), receiver = xyPatch(2, 8, 8);
    HiddenSampleMap map(16, 8, 8);
    const std::vector<int> subset = {0, 9, 63};
    EXPECT_EQ(caster.sampleUnblocked(source, receiver, map, {.receiverSubset = &subset}), 3u * 16u);
    for (int j = 0; j < 64; ++j)
        EXPECT_EQ(map.blockedCount(j), j == 0 || j == 9 || j == 63 ? 16 : 0) << j;
    const std::vector<int> outside = {64};
    EXPECT_THROW(caster.sampleUnblocked(source, receiver, map, {.receiverSubset = &outside}), Error);
}

TEST(SourceJitter, OffsetsAreDecorrelatedAndWithinHalfACell)
{
    const SourceJitter off, on{.seed = 7}, other{.seed = 8};
    EXPECT_EQ(off.offset(5), glm::dvec2(0.0));
    glm::dvec2 mean(0.0);
    int differ = 0;
    for (int j = 0; j < 4096; ++j) {
        const glm::dvec2 o = on.offset(j);
        EXPECT_GE(o.x, -0.5);
        EXPECT_LT(o.x, 0.5);
        EXPECT_GE(o.y, -0.5);
        EXPECT_LT(o.y, 0.5);
        EXPECT_EQ(o, on.offset(j));   // reproducible
        mean += o;
        differ += o != other.offset(j);
        if (j > 0) {
            EXPECT_NE(o, on.offset(j - 1));
        }
    }
    EXPECT_LT(std::abs(mean.x / 4096), 0.02);
    EXPECT_LT(std::abs(mean.y / 4096), 0.02);
    EXPECT_EQ(differ, 4096);
}

TEST(CpuBitmaskSampler, JitteredSamplesMatchTheReferenceAtTheShiftedPositions)
{
    // Decorrelated sampling (§6.2): each receiver sample sees its own shifted source grid. The
    // reference and brute force cast to the shifted positions; every CPU strategy and both
    // kernels must give that answer, and it must differ from the unjittered one.
    const SourceJitter jitter{.seed = 12345};
    int checked = 0;
    std::uint64_t changed = 0;
    for (unsigned seed = 1; seed <= 20; ++seed) {
        const RandomCase c = randomCase(seed);
        if (!c.valid())
            continue;
        ++checked;
        const BruteForceMap reference = bruteForceSample(worldTriangles(c.scene), c.source, c.receiver, 1e-5, jitter);
        const HiddenSampleMap embree = RayCastScene(c.scene).sample(c.source, c.receiver, {.jitter = jitter});
        EXPECT_EQ(mismatchesOutsideGrazing(embree, reference), 0u) << "reference, seed " << seed;
        const CpuBitmaskSampler sampler(c.scene);
        for (const bool simd : {true, false})
            for (const CpuStrategy strategy : {CpuStrategy::Bitmask, CpuStrategy::Hybrid, CpuStrategy::RayCast}) {
                const HiddenSampleMap map =
                    sampler.sample(c.source, c.receiver, {.strategy = strategy, .smallCells = 4.0, .simd = simd, .jitter = jitter});
                EXPECT_EQ(mismatchesOutsideGrazing(map, reference), 0u)
                    << "seed " << seed << ", strategy " << int(strategy) << (simd ? ", simd" : ", scalar");
            }
        changed += sampler.sample(c.source, c.receiver, {.jitter = jitter})
                       .differenceCount(sampler.sample(c.source, c.receiver));
    }
    EXPECT_GE(checked, 15);
    EXPECT_GT(changed, 0u);
}

TEST(RayCastSampler, JitteredHalfPlaneMatchesTheFormula)
{
    const double edge = 0.437;
    const Scene scene = sceneOf({quad({-50, -50, 1}, {50 + float(edge), 0, 0}, {0, 100, 0})});
    const Patch source = xyPatch(0, 13, 7), receiver = xyPatch(3, 52, 9);
    const SourceJitter jitter{.seed = 99};
    const HiddenSampleMap map = RayCastScene(scene).sample(source, receiver, {.jitter = jitter});
    const HiddenSampleMap cpu = CpuBitmaskSampler(scene).sample(source, receiver, {.jitter = jitter});
    std::uint64_t mismatches = 0, cpuMismatches = 0;
    for (int j = 0; j < receiver.sampleCount(); ++j)
        for (int i = 0; i < source.sampleCount(); ++i) {
            const glm::dvec3 s = source.sample(i) + jitter.shift(source, j);
            const bool blocked = s.x + (receiver.sample(j).x - s.x) / 3.0 < edge;
            mismatches += blocked != map.blocked(j, i);
            cpuMismatches += blocked != cpu.blocked(j, i);
        }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_EQ(cpuMismatches, 0u);
}

TEST(TileBins, SortLargestFirstIsStableAndOrdersSizesToTheirRank)
{
    // Sizes as the bins meet them: zeros (edge-on), the whole-region marker 1e300, near-equal
    // sizes, repeats, and random magnitudes over thirty octaves.
    std::mt19937 rng(11);
    std::vector<double> cells = {0.0, 1e300, 3.0, 3.0, 3.0 * (1.0 + 1e-9), 3.0 * (1.0 + 1e-3), 0.5, 1e300, 0.0};
    std::uniform_real_distribution<double> exponent(-10.0, 20.0);
    for (int i = 0; i < 5000; ++i)
        cells.push_back(std::exp2(exponent(rng)));
    std::vector<bitmask::SizeKey> keys, scratch;
    for (std::size_t i = 0; i < cells.size(); ++i)
        keys.push_back({bitmask::sizeRank(cells[i]), std::uint32_t(i)});
    bitmask::sortLargestFirst(keys, scratch);
    ASSERT_EQ(keys.size(), cells.size());
    std::vector<char> seen(cells.size(), 0);
    for (std::size_t n = 0; n < keys.size(); ++n) {
        ASSERT_FALSE(seen[keys[n].occluder]) << "a permutation";
        seen[keys[n].occluder] = 1;
        if (n == 0)
            continue;
        const bitmask::SizeKey& before = keys[n - 1];
        const bitmask::SizeKey& after = keys[n];
        ASSERT_LE(before.rank, after.rank);
        if (before.rank == after.rank) {
            ASSERT_LT(before.occluder, after.occluder) << "equal ranks keep their order";
        }
        // Never a size more than 2^-12 larger after a smaller one.
        ASSERT_GE(cells[before.occluder] * (1.0 + std::exp2(-12.0)), cells[after.occluder]) << n;
    }
    EXPECT_EQ(keys.front().occluder, 1u);   // 1e300, then its repeat
    EXPECT_EQ(keys[1].occluder, 7u);
    EXPECT_EQ(keys[keys.size() - 2].occluder, 0u);   // the zeros last, in order
    EXPECT_EQ(keys.back().occluder, 8u);
    // 3.0 and 3.0 (1 + 1e-9) share a rank; 3.0 (1 + 1e-3) does not.
    EXPECT_EQ(bitmask::sizeRank(3.0), bitmask::sizeRank(3.0 * (1.0 + 1e-9)));
    EXPECT_LT(bitmask::sizeRank(3.0 * (1.0 + 1e-3)), bitmask::sizeRank(3.0));
    EXPECT_EQ(bitmask::sizeRank(std::nan("")), bitmask::sizeRank(0.0)) << "no NaN reaches here; if one did, last";
}
