// What an approximation costs, ray by ray (visibility/RayDisagreement.h): differences sorted by the
// exact judge into false-blocked, false-free and ties; fewer samples stood in for every ray; the
// picture of every ray.
#include <gtest/gtest.h>

#include <random>

#include "ExactJudge.h"
#include "TestScenes.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/RayDisagreement.h"

using namespace sightline;
using namespace sightline::test;

namespace {

HiddenSampleMap randomMap(int sources, int na, int nb, unsigned seed, double blockedShare)
{
    HiddenSampleMap map(sources, na, nb);
    std::mt19937 rng(seed);
    std::bernoulli_distribution blocked(blockedShare);
    for (int j = 0; j < map.receiverCount(); ++j)
        for (int i = 0; i < sources; ++i)
            if (blocked(rng))
                map.setBlocked(j, i);
    return map;
}

/// A wall at z = 1 over x < 0.5 between two 8 x 8 patches at z = 0 and z = 2 whose grids line up
/// (rays parallel to z from sample to sample): the rays of column a = 4 (x = 0.5625) pass 6 cm
/// from its edge, and with the edge moved onto a sample column (x = 0.5625) they graze it: ties.
Scene wallUpTo(double edgeX) { return sceneOf({quad({-1.0f, -1.0f, 1.0f}, {float(edgeX) + 1.0f, 0.0f, 0.0f}, {0.0f, 3.0f, 0.0f})}); }

} // namespace

TEST(RayDisagreement, WithoutAJudgeEveryDifferenceIsAnErrorSortedByTheExactMap)
{
    const HiddenSampleMap exact = randomMap(100, 7, 5, 1, 0.4), approximate = randomMap(100, 7, 5, 2, 0.5);
    const RayDisagreement d = rayDisagreement(exact, approximate, nullptr);
    EXPECT_FALSE(d.judged);
    EXPECT_EQ(d.rays, exact.rayCount());
    std::uint64_t falseBlocked = 0, falseFree = 0;
    for (int j = 0; j < exact.receiverCount(); ++j)
        for (int i = 0; i < 100; ++i) {
            const bool e = exact.blocked(j, i), a = approximate.blocked(j, i);
            EXPECT_EQ(d.falseBlocked.blocked(j, i), a && !e);
            EXPECT_EQ(d.falseFree.blocked(j, i), e && !a);
            EXPECT_FALSE(d.ties.blocked(j, i));
            falseBlocked += a && !e, falseFree += e && !a;
        }
    EXPECT_EQ(d.falseBlockedCount, falseBlocked);
    EXPECT_EQ(d.falseFreeCount, falseFree);
    EXPECT_GT(falseBlocked, 0u);
    EXPECT_GT(falseFree, 0u);
    EXPECT_EQ(d.falseBlockedCount + d.falseFreeCount, exact.differenceCount(approximate));
}

TEST(RayDisagreement, TheJudgeSortsFlippedRaysAndPutsGrazingOnesApartAsTies)
{
    const Patch source = xyPatch(0.0, 8, 8), receiver = xyPatch(2.0, 8, 8);
    for (const bool grazing : {false, true}) {
        const Scene level = wallUpTo(grazing ? 0.5625 : 0.5);
        const HiddenSampleMap exact = CpuBitmaskSampler(level).sample(source, receiver);
        const ExactJudge judge(worldTriangles(level), source, receiver);
        // Flip the straight rays of column a = 4 (just past the edge, or on it) and one clearly
        // blocked straight ray (column 1).
        HiddenSampleMap approximate = exact;
        std::uint64_t flippedFree = 0, flippedBlocked = 0;
        for (int b = 0; b < 8; ++b)
            for (const int a : {1, 4}) {
                const int k = b * 8 + a;
                const bool wasBlocked = exact.blocked(k, k);
                approximate.row(k)[std::size_t(k) >> 6] ^= std::uint64_t(1) << (k & 63);
                (wasBlocked ? flippedBlocked : flippedFree) += 1;
            }
        const RayDisagreement d = rayDisagreement(exact, approximate, &judge);
        ASSERT_TRUE(d.judged);
        EXPECT_EQ(d.exactErrors, 0u);
        EXPECT_EQ(d.falseFreeCount, grazing ? 8u : flippedBlocked) << "column 1 is blocked: dropping it is false-free";
        EXPECT_EQ(d.falseBlockedCount, grazing ? 0u : flippedFree) << "column 4 passes 6 cm beside the edge: free";
        EXPECT_EQ(d.tieCount, grazing ? 8u : 0u) << "column 4 grazing the edge: either answer is allowed";
        for (int b = 0; b < 8; ++b) {
            const int k = b * 8 + 4;
            EXPECT_EQ(d.ties.blocked(k, k), grazing);
            EXPECT_EQ(d.falseBlocked.blocked(k, k), !grazing);
            EXPECT_TRUE(d.falseFree.blocked(b * 8 + 1, b * 8 + 1));
        }
    }
}

TEST(RayDisagreement, PastTheCapNothingIsJudged)
{
    const Patch source = xyPatch(0.0, 8, 8), receiver = xyPatch(2.0, 8, 8);
    const Scene level = wallUpTo(0.5);
    const HiddenSampleMap exact = CpuBitmaskSampler(level).sample(source, receiver);
    const ExactJudge judge(worldTriangles(level), source, receiver);
    const HiddenSampleMap none(64, 8, 8);
    const RayDisagreement d = rayDisagreement(exact, none, &judge, exact.blockedCount() - 1);
    EXPECT_FALSE(d.judged);
    EXPECT_EQ(d.falseFreeCount, exact.blockedCount());
    const RayDisagreement judged = rayDisagreement(exact, none, &judge, exact.blockedCount());
    EXPECT_TRUE(judged.judged);
    EXPECT_EQ(judged.falseFreeCount + judged.tieCount, exact.blockedCount());
}

TEST(RayDisagreement, FewerSamplesStandForTheRaysOfTheirCells)
{
    Patch source = xyPatch(0.0, 5, 4), receiver = xyPatch(2.0, 7, 3);
    const Patch coarseSource = withFewerSamples(source, 2), coarseReceiver = withFewerSamples(receiver, 2);
    EXPECT_EQ(coarseSource.na, 3);
    EXPECT_EQ(coarseSource.nb, 2);
    EXPECT_EQ(coarseReceiver.na, 4);
    EXPECT_EQ(coarseReceiver.nb, 2);
    EXPECT_EQ(withFewerSamples(xyPatch(0.0, 1, 3), 4).na, 1);
    const HiddenSampleMap coarse = randomMap(coarseSource.sampleCount(), coarseReceiver.na, coarseReceiver.nb, 3, 0.5);
    const HiddenSampleMap full = spreadToFullGrids(coarse, coarseSource, coarseReceiver, source, receiver);
    ASSERT_EQ(full.sourceCount(), 20);
    ASSERT_EQ(full.receiverCount(), 21);
    // The coarse cell holding a full sample's position, found geometrically.
    auto cellOf = [](const Patch& fine, const Patch& coarser, int k) {
        const glm::dvec3 p = fine.sample(k);
        const int a = int((p.x - fine.corner.x) / glm::length(fine.u) * coarser.na);
        const int b = int((p.y - fine.corner.y) / glm::length(fine.v) * coarser.nb);
        return b * coarser.na + a;
    };
    for (int j = 0; j < receiver.sampleCount(); ++j)
        for (int i = 0; i < source.sampleCount(); ++i)
            EXPECT_EQ(full.blocked(j, i), coarse.blocked(cellOf(receiver, coarseReceiver, j), cellOf(source, coarseSource, i)))
                << j << " " << i;
}

TEST(RayDisagreement, ThePictureHasAPixelPerRayInColoursThatCountTheClasses)
{
    const HiddenSampleMap exact = randomMap(12, 3, 2, 4, 0.5), approximate = randomMap(12, 3, 2, 5, 0.5);
    RayDisagreement d = rayDisagreement(exact, approximate, nullptr);
    d.ties.setBlocked(5, 11);   // a tie, drawn amber over whatever else the ray is
    const DisagreementImage image = disagreementImage(exact, d, 4, 3);
    ASSERT_EQ(image.width, 3 * 5 - 1);
    ASSERT_EQ(image.height, 2 * 4 - 1);
    EXPECT_EQ(image.raysPerPixelSide, 1);
    auto pixelIs = [&](int x, int y, const std::uint8_t rgb[3]) {
        const std::uint8_t* p = image.rgb.data() + (std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 3;
        return p[0] == rgb[0] && p[1] == rgb[1] && p[2] == rgb[2];
    };
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 12; ++i) {
            const int x = (j % 3) * 5 + i % 4, y = (j / 3) * 4 + i / 4;
            EXPECT_EQ(pixelIs(x, y, kFalseBlockedRgb), d.falseBlocked.blocked(j, i));
            EXPECT_EQ(pixelIs(x, y, kFalseFreeRgb), d.falseFree.blocked(j, i));
        }
    EXPECT_TRUE(pixelIs(2 * 5 + 3, 1 * 4 + 2, d.falseBlocked.blocked(5, 11) ? kFalseBlockedRgb
                                                 : d.falseFree.blocked(5, 11) ? kFalseFreeRgb : kTieRgb));
    // Too large for one pixel a ray: blocks of k x k rays, a disagreement's colour winning.
    const DisagreementImage small = disagreementImage(exact, d, 4, 3, 6);
    EXPECT_EQ(small.raysPerPixelSide, 2);
    EXPECT_EQ(small.width, 6);
    EXPECT_EQ(small.height, 3);
    const bool anyFalseBlocked = d.falseBlocked.blocked(0, 0) || d.falseBlocked.blocked(0, 1) ||
                                 d.falseBlocked.blocked(0, 4) || d.falseBlocked.blocked(0, 5);
    EXPECT_EQ(std::equal(small.rgb.begin(), small.rgb.begin() + 3, kFalseBlockedRgb), anyFalseBlocked);
}
