// The CPU sampler's ray casting (raycast/ProvenRayCaster.h): the reference's answer bit for bit,
// on the adversarial suite at production sizes and 0-100 km from the origin, both ways of
// traversing and both ends to start from; every hit its proof accepts is a crossing by the
// contract's own double test.

#include <gtest/gtest.h>

#include "AdversarialScenes.h"
#include "ExactnessSuite.h"
#include "TestScenes.h"
#include "raycast/ProvenRayCaster.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
using namespace sightline::test;
using raycast::CastMode;
using raycast::ProvenCastStats;
using raycast::ProvenRayCaster;

namespace {

/// Rays where two maps of the same pair differ.
std::uint64_t differingRays(const HiddenSampleMap& a, const HiddenSampleMap& b)
{
    std::uint64_t count = 0;
    for (int j = 0; j < a.receiverCount(); ++j)
        for (std::size_t w = 0; w < a.row(j).size(); ++w)
            count += std::uint64_t(std::popcount(a.row(j)[w] ^ b.row(j)[w]));
    return count;
}

struct SuiteCounts {
    std::uint64_t rays = 0, proven = 0, exact = 0, confirmed = 0, differing = 0;
    int fromSource = 0, fromReceiver = 0;
};

/// Every case of the suite with a receiver grid of `side` (the source's is 32x32, or 32x1): the
/// caster in `mode` against the reference, with the proof checked on every hit it accepts.
SuiteCounts compareOnSuite(const std::vector<double>& offsets, int seeds, CastMode mode, Variant variant)
{
    SuiteCounts counts;
    const std::vector<AdversarialCase> cases = suite(offsets, seeds);
    for (std::size_t n = 0; n < cases.size(); ++n) {
        const AdversarialCase& c = cases[n];
        // Half the cases with a coarse receiver, so that rays also start at the receiver.
        Patch receiver = c.receiver;
        if (n % 2 == 1)
            receiver.na = receiver.nb = 8;
        RayCastOptions options;
        ReceiverHeights heights;
        if (variant == Variant::Jittered)
            options.jitter.seed = std::uint32_t(n + 1);
        if (variant == Variant::Bumpy) {
            heights = randomHeights(receiver, unsigned(n + 1), 0.1 * glm::length(receiver.centre() - c.source.centre()));
            options.heights = &heights;
        }
        const WorldTriangles triangles = worldTriangles(c.scene);
        const RayCastScene reference(triangles);
        ProvenRayCaster caster(triangles);
        caster.setVerifyProofs(true);
        const HiddenSampleMap truth = reference.sample(c.source, receiver, options);
        HiddenSampleMap map(c.source.sampleCount(), receiver.na, receiver.nb);
        ProvenCastStats stats;
        caster.sampleUnblocked(c.source, receiver, map, options, reference, mode, &stats);
        const std::uint64_t differ = differingRays(map, truth);
        EXPECT_EQ(differ, 0u) << c.name;
        EXPECT_EQ(caster.proofContradictions(), 0u) << c.name;
        counts.differing += differ;
        counts.rays += map.rayCount();
        counts.proven += stats.provenHits;
        counts.exact += stats.exactTests;
        counts.confirmed += stats.confirmRays;
        (stats.fromSource ? counts.fromSource : counts.fromReceiver) += 1;
    }
    std::printf("%llu rays: %llu hits proven, %llu tested exactly, %llu confirmed by the reference; %d cases from the "
                "source, %d from the receiver\n",
                (unsigned long long)counts.rays, (unsigned long long)counts.proven, (unsigned long long)counts.exact,
                (unsigned long long)counts.confirmed, counts.fromSource, counts.fromReceiver);
    return counts;
}

} // namespace

TEST(ProvenRayCaster, AnswersAsTheReferenceOnAdversarialScenesWithPackets)
{
    const SuiteCounts counts = compareOnSuite({0.0, 1e3, 1e4, 1e5}, seeds(2), CastMode::Packets, Variant::Plain);
    // Both ends to start from, and most hits decided by the proof alone.
    EXPECT_GT(counts.fromSource, 0);
    EXPECT_GT(counts.fromReceiver, 0);
    EXPECT_GT(counts.proven, 10 * counts.exact);
}

TEST(ProvenRayCaster, AnswersAsTheReferenceOnAdversarialScenesWithTheOcclusionTraversal)
{
    // Hits are accepted in the filter and proven after the call; those at a patch are passed over.
    const SuiteCounts counts = compareOnSuite({0.0, 1e3, 1e4, 1e5}, seeds(2), CastMode::Occluded, Variant::Plain);
    EXPECT_GT(counts.fromSource, 0);
    EXPECT_GT(counts.fromReceiver, 0);
    EXPECT_GT(counts.proven, 10 * counts.exact);
}

TEST(ProvenRayCaster, AnswersAsTheReferenceWithJitterAndBumps)
{
    compareOnSuite({0.0, 1e4}, seeds(1), CastMode::Auto, Variant::Jittered);
    compareOnSuite({0.0, 1e4}, seeds(1), CastMode::Auto, Variant::Bumpy);
}

TEST(ProvenRayCaster, CastsOnlyTheGivenReceiverSamples)
{
    const Scene scene = sceneOf({quad({0.2f, 0.1f, 1}, {0.5f, 0, 0}, {0, 0.7f, 0})});
    const WorldTriangles triangles = worldTriangles(scene);
    const RayCastScene reference(triangles);
    const ProvenRayCaster caster(triangles);
    const Patch source = xyPatch(0, 32, 32), receiver = xyPatch(2, 32, 32);
    const HiddenSampleMap truth = reference.sample(source, receiver);
    const std::vector<int> subset = {0, 5, 33, 100, 101, 102, 1023};
    for (const CastMode mode : {CastMode::Packets, CastMode::Occluded}) {
        HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
        caster.sampleUnblocked(source, receiver, map, {.receiverSubset = &subset}, reference, mode);
        for (int j = 0; j < receiver.sampleCount(); ++j) {
            const bool chosen = std::find(subset.begin(), subset.end(), j) != subset.end();
            EXPECT_EQ(map.blockedCount(j), chosen ? truth.blockedCount(j) : 0) << j;
        }
    }
}

TEST(ProvenRayCaster, AutoTimesBothWaysOnceForSimilarCalls)
{
    // The first call times packets against the occlusion traversal on a few blocks; the next calls on a
    // similar configuration take that choice, and every answer is the reference's.
    const Scene scene = sceneOf({quad({0.2f, 0.1f, 1}, {0.5f, 0, 0}, {0, 0.7f, 0}), quad({0.5f, 0.4f, 1.5f}, {0.3f, 0, 0}, {0, 0.3f, 0})});
    const WorldTriangles triangles = worldTriangles(scene);
    const RayCastScene reference(triangles);
    const ProvenRayCaster caster(triangles);
    const Patch source = xyPatch(0, 8, 8);
    {
        // A call on a few receiver samples (Auto's probe casts a few tiles at a time) is too
        // small to time: it neither times nor leaves a choice for the next calls.
        const Patch receiver = xyPatch(2, 32, 32);
        const std::vector<int> few = {0, 1, 2, 3, 32, 33, 34, 35};
        HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
        ProvenCastStats stats;
        caster.sampleUnblocked(source, receiver, map, {.receiverSubset = &few}, reference, CastMode::Auto, &stats);
        EXPECT_FALSE(stats.probedMode);
    }
    for (int call = 0; call < 3; ++call) {
        Patch receiver = xyPatch(2, 32, 32);
        receiver.corner.x += 0.01 * call;
        HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
        ProvenCastStats stats;
        caster.sampleUnblocked(source, receiver, map, {}, reference, CastMode::Auto, &stats);
        EXPECT_EQ(stats.probedMode, call == 0) << call;
        EXPECT_EQ(differingRays(map, reference.sample(source, receiver)), 0u) << call;
    }
}

TEST(ProvenRayCaster, PacketsFromTheSourceInTheReferenceAnswerAsFromTheReceiver)
{
    // RayCastOptions::fromSource: the same map bit for bit, at the origin and 10 km out.
    for (const double offset : {0.0, 1e4})
        for (int seed = 1; seed <= seeds(1); ++seed)
            for (const Adversary kind : allAdversaries()) {
                const AdversarialCase c = adversarialCase(kind, unsigned(seed), offset);
                const RayCastScene reference(c.scene);
                const HiddenSampleMap a = reference.sample(c.source, c.receiver);
                const HiddenSampleMap b = reference.sample(c.source, c.receiver, {.fromSource = true});
                EXPECT_EQ(differingRays(a, b), 0u) << c.name;
            }
}
