// Occluder suggestions (project/SuggestedOccluder.h) at production sizes: each one inserted
// leaves at most the rays it promised, by the exact sampler and by docs/design.md §2's exact
// judge asked about every ray that was unblocked before (zero disagreements outside ties), on
// the demo level, the generated bench levels, the natural floor-to-wall pair, a bumpy receiver
// and every adversarial category, near the origin and a kilometre out.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "AdversarialScenes.h"
#include "ExactJudge.h"
#include "TestScenes.h"
#include "demo/BenchScenes.h"
#include "demo/DemoLevel.h"
#include "project/SuggestedOccluder.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"

using namespace sightline;
using namespace sightline::test;

namespace {

/// A request on the plane at `depth` for `share` of the rays, as `shape` (the rest defaulted).
suggest::Request request(double depth, double share, suggest::Shape shape)
{
    suggest::Request r;
    r.depth = depth;
    r.share = share;
    r.shape = shape;
    return r;
}

struct SuggestCase {
    std::string name;
    Scene scene;
    Patch source, receiver;
    ReceiverHeights heights;
};

HiddenSampleMap exactMap(const Scene& scene, const SuggestCase& c)
{
    BitmaskOptions options;
    options.heights = c.heights.empty() ? nullptr : &c.heights;
    return CpuBitmaskSampler(scene).sample(c.source, c.receiver, options);
}

/// Suggests, then checks the promise twice over: the exact sampler on the scene with the
/// occluder, and the exact judge on the occluder alone over every ray unblocked before (adding
/// an occluder changes only those). Returns the suggestion for further checks.
SuggestedOccluder checkSuggestion(const SuggestCase& c, const suggest::Request& request)
{
    const std::string what = c.name + ", depth " + std::to_string(request.depth) + ", share " +
                             std::to_string(request.share) + ", " + suggest::shapeName(request.shape);
    const SuggestedOccluder s = suggestOnScene(c.scene, c.source, c.receiver, c.heights, request, "suggested", "s.glb");
    EXPECT_LE(s.unblockedAfter, s.suggestion.promised) << what;
    EXPECT_EQ(s.attempts, 1) << what << ": the first margin should already be wide enough";
    EXPECT_GE(s.suggestion.enclosed, s.suggestion.required) << what;
    EXPECT_GT(s.suggestion.area, 0.0) << what;

    const HiddenSampleMap before = exactMap(c.scene, c);
    Scene with = c.scene;
    appendOccluder(with, s.mesh, s.spec);
    const HiddenSampleMap after = exactMap(with, c);
    EXPECT_EQ(after.rayCount() - after.blockedCount(), s.unblockedAfter) << what;

    Scene alone;
    appendOccluder(alone, s.mesh, s.spec);
    std::vector<glm::dvec3> displaced;
    for (int j = 0; j < c.receiver.sampleCount(); ++j)
        displaced.push_back(displacedReceiverSample(c.source, c.receiver, c.heights, j));
    const ExactJudge judge(worldTriangles(alone), c.source, c.receiver, {}, &displaced);
    std::uint64_t free = 0, ties = 0, disagreements = 0;
    for (int j = 0; j < c.receiver.sampleCount(); ++j)
        for (int i = 0; i < c.source.sampleCount(); ++i) {
            if (before.blocked(j, i))
                continue;
            const RayKind kind = judge.ray(j, i);
            free += kind == RayKind::Free;
            ties += kind == RayKind::EdgeTie || kind == RayKind::EndTie;
            disagreements += (kind == RayKind::Free && after.blocked(j, i)) || (kind == RayKind::Blocked && !after.blocked(j, i));
        }
    EXPECT_LE(free, s.suggestion.promised) << what << " (" << ties << " ties)";
    EXPECT_EQ(disagreements, 0u) << what;
    return s;
}

SuggestCase facingSquares(double gap, glm::dvec3 offset = glm::dvec3(0.0))
{
    SuggestCase c;
    c.name = "facing squares " + std::to_string(gap) + " m apart";
    c.source = xyPatch(0.0, 32, 32);
    c.receiver = xyPatch(gap, 32, 32);
    c.source.corner += offset;
    c.receiver.corner += offset;
    return c;
}

SuggestCase demoCase()
{
    const demo::DemoView view = demo::demoView();
    return {"demo level", demo::makeDemoLevel(), view.source, view.receiver, {}};
}

/// The most natural pair: a floor patch and a wall patch above its plane, a crate between them.
SuggestCase floorToWall()
{
    SuggestCase c;
    c.name = "floor to wall";
    c.scene = sceneOf({quad({1.6f, 0.0f, -0.2f}, {0.0f, 0.0f, 0.4f}, {0.0f, 0.9f, 0.0f}, "crate side")});
    c.source.corner = {0.0, 0.02, -0.5};
    c.source.u = {0.0, 0.0, 1.0};
    c.source.v = {1.0, 0.0, 0.0};   // normal +y
    c.receiver.corner = {3.99, 0.3, -0.5};
    c.receiver.u = {0.0, 0.0, 1.0};
    c.receiver.v = {0.0, 1.5, 0.0};   // normal -x, facing the floor patch
    return c;
}

} // namespace

TEST(Suggest, OpenViewGivesTheHullOfTheCrossingsAsTheContractSays)
{
    // Nothing between two equal squares: at any depth the crossings (1 - T) S + T R fill a square
    // of side 31/32 m (the samples' span), so the smallest convex occluder and the smallest
    // rectangle are that square, grown by the margin.
    const SuggestCase c = facingSquares(2.0);
    for (const double depth : {0.25, 0.5, 0.8})
        for (const suggest::Shape shape : {suggest::Shape::Convex, suggest::Shape::Rect}) {
            const SuggestedOccluder s = checkSuggestion(c, request(depth, 1.0, shape));
            const double side = 31.0 / 32.0, margin = s.suggestion.margin;
            EXPECT_GE(s.suggestion.area, side * side);
            EXPECT_LE(s.suggestion.area, (side + 2.0 * margin) * (side + 2.0 * margin) + 1e-12);
            EXPECT_EQ(s.suggestion.unblockedBefore, 1024u * 1024u);
            EXPECT_EQ(s.suggestion.promised, 0u);
            EXPECT_EQ(s.unblockedAfter, 0u);
        }
}

TEST(Suggest, ShareBelowOneBlocksAtLeastThatShareWithASmallerOccluder)
{
    const SuggestCase c = facingSquares(3.0);
    const SuggestedOccluder all = checkSuggestion(c, request(0.5, 1.0, suggest::Shape::Convex));
    for (const suggest::Shape shape : {suggest::Shape::Convex, suggest::Shape::Rect})
        for (const double share : {0.95, 0.5}) {
            const SuggestedOccluder part = checkSuggestion(c, request(0.5, share, shape));
            EXPECT_LT(part.suggestion.area, all.suggestion.area) << share;
            EXPECT_EQ(part.suggestion.promised, std::uint64_t(1024 * 1024) - part.suggestion.required);
            EXPECT_GE(double(part.suggestion.required), share * 1024.0 * 1024.0 - 1.0);
        }
}

TEST(Suggest, DemoLevelAtProductionSizes)
{
    const SuggestCase c = demoCase();
    for (const double depth : {0.3, 0.5, 0.7})
        for (const suggest::Shape shape : {suggest::Shape::Convex, suggest::Shape::Rect}) {
            const SuggestedOccluder s = checkSuggestion(c, request(depth, 1.0, shape));
            EXPECT_EQ(s.unblockedAfter, 0u) << depth;
            checkSuggestion(c, request(depth, 0.9, shape));
        }
}

TEST(Suggest, GeneratedLevelsOnSeveralSeeds)
{
    for (const demo::BenchKind kind : {demo::BenchKind::ClutteredRooms, demo::BenchKind::ArchitecturalInterior})
        for (const std::uint64_t seed : {1u, 2u}) {
            const demo::BenchScene bench = demo::makeBenchScene(kind, seed);
            const SuggestCase c{bench.name, bench.scene, bench.source, bench.receiver, {}};
            checkSuggestion(c, request(0.4, 1.0, suggest::Shape::Convex));
            checkSuggestion(c, request(0.6, 0.95, suggest::Shape::Rect));
        }
}

TEST(Suggest, FloorToWallPairAndABumpyReceiver)
{
    SuggestCase c = floorToWall();
    checkSuggestion(c, request(0.5, 1.0, suggest::Shape::Convex));
    checkSuggestion(c, request(0.5, 1.0, suggest::Shape::Rect));
    SuggestCase bumpy = facingSquares(2.0);
    bumpy.name = "bumpy receiver";
    bumpy.heights = randomHeights(bumpy.receiver, 3, 0.3);
    checkSuggestion(bumpy, request(0.5, 1.0, suggest::Shape::Convex));
    checkSuggestion(bumpy, request(0.7, 0.95, suggest::Shape::Rect));
}

TEST(Suggest, KilometresFromTheOrigin)
{
    for (const double distance : {1e3, 1e4, 1e5}) {
        const SuggestCase c = facingSquares(2.0, glm::dvec3(distance, -0.6 * distance, 0.3 * distance));
        checkSuggestion(c, request(0.5, 1.0, suggest::Shape::Convex));
        checkSuggestion(c, request(0.35, 1.0, suggest::Shape::Rect));
    }
}

TEST(Suggest, EveryAdversarialCategory)
{
    int suggested = 0, refused = 0;
    for (const Adversary kind : allAdversaries())
        for (const unsigned seed : {1u, 2u})
            for (const double offset : {0.0, 1000.0}) {
                AdversarialCase a = adversarialCase(kind, seed, offset);
                const SuggestCase c{a.name, std::move(a.scene), a.source, a.receiver, {}};
                const suggest::Shape shape = seed == 1 ? suggest::Shape::Convex : suggest::Shape::Rect;
                try {
                    checkSuggestion(c, request(0.5, 1.0, shape));
                    ++suggested;
                } catch (const Error& e) {
                    // Only the two refusals the contract allows: nothing left to cut, or rays
                    // that do not cross the plane.
                    const std::string message = e.what();
                    EXPECT_TRUE(message.find("already blocked") != std::string::npos ||
                                message.find("do not cross it") != std::string::npos)
                        << c.name << ": " << message;
                    ++refused;
                }
            }
    EXPECT_GE(suggested, 3 * refused) << "most adversarial pairs have a plane between them";
}

TEST(Suggest, RefusalsSayWhy)
{
    SuggestCase c = facingSquares(2.0);
    EXPECT_THROW(checkSuggestion(c, request(0.0, 1.0, suggest::Shape::Convex)), Error);
    EXPECT_THROW(checkSuggestion(c, request(1.0, 1.0, suggest::Shape::Convex)), Error);
    EXPECT_THROW(checkSuggestion(c, request(0.5, 0.0, suggest::Shape::Convex)), Error);
    EXPECT_THROW(checkSuggestion(c, request(0.5, 1.5, suggest::Shape::Convex)), Error);
    c.scene = sceneOf({quad({-5.0f, -5.0f, 1.0f}, {10.0f, 0.0f, 0.0f}, {0.0f, 10.0f, 0.0f}, "wall")});
    try {
        suggestOnScene(c.scene, c.source, c.receiver, {}, request(0.5, 1.0, suggest::Shape::Convex), "s", "s.glb");
        ADD_FAILURE() << "a closed view has nothing to cut";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("already blocked"), std::string::npos) << e.what();
    }
}

// Below share 1, weighted by the light each ray carries: a source whose left half is ten times as
// bright as its right. The occluder keeps its promise in light as well as in rays (by the exact
// sampler and the judge). A dark right half leaves only the left half's rays to block: a smaller
// occluder than for the same share of every ray. Weights all 1 give the count's answer itself.
TEST(Suggest, ImportanceWeightedShareBlocksTheLightAsked)
{
    const std::pair<SuggestCase, suggest::Shape> cases[] = {{demoCase(), suggest::Shape::Convex},
                                                            {floorToWall(), suggest::Shape::Rect}};
    for (const auto& [c, shape] : cases) {
        std::vector<double> bright(std::size_t(c.source.sampleCount()), 1.0), dark = bright, ones = bright;
        for (int i = 0; i < c.source.sampleCount(); ++i) {
            const bool left = i % c.source.na < c.source.na / 2;
            bright[std::size_t(i)] = left ? 10.0 : 1.0;
            dark[std::size_t(i)] = left ? 1.0 : 0.0;
        }
        const suggest::Request counted = request(0.5, 0.8, shape);
        suggest::Request weighted = counted;
        weighted.sourceWeights = bright;
        const SuggestedOccluder w = checkSuggestion(c, weighted);
        const suggest::Suggestion& s = w.suggestion;
        ASSERT_TRUE(s.weighted);
        EXPECT_NEAR(s.lightBefore, suggest::unblockedLight(exactMap(c.scene, c), bright), 1e-9 * s.lightBefore);
        EXPECT_NEAR(s.lightRequired, 0.8 * s.lightBefore, 1e-9 * s.lightBefore);
        EXPECT_GE(s.lightEnclosed, s.lightRequired * (1.0 - 1e-12)) << c.name;
        EXPECT_LE(w.lightAfter, s.lightBefore - s.lightEnclosed + 1e-9 * s.lightBefore) << c.name;

        const suggest::Suggestion n = suggestOnScene(c.scene, c.source, c.receiver, c.heights, counted, "s", "s.glb").suggestion;
        suggest::Request alike = counted;
        alike.sourceWeights = ones;
        const suggest::Suggestion a = suggestOnScene(c.scene, c.source, c.receiver, c.heights, alike, "s", "s.glb").suggestion;
        EXPECT_NEAR(a.area, n.area, 1e-9 * n.area) << c.name;
        suggest::Request half = counted;
        half.sourceWeights = dark;
        const SuggestedOccluder h = checkSuggestion(c, half);
        EXPECT_LT(h.suggestion.area, n.area) << c.name;
        EXPECT_LE(h.lightAfter, (1.0 - 0.8) * h.suggestion.lightBefore * (1.0 + 1e-9)) << c.name;
    }
    // Refusals: weights that are not light, or no light at all.
    const SuggestCase c = floorToWall();
    suggest::Request bad = request(0.5, 0.8, suggest::Shape::Convex);
    bad.sourceWeights = std::vector<double>(std::size_t(c.source.sampleCount()), 0.0);
    EXPECT_THROW(suggestOnScene(c.scene, c.source, c.receiver, c.heights, bad, "s", "s.glb"), Error);
    bad.sourceWeights[0] = std::nan("");
    EXPECT_THROW(suggestOnScene(c.scene, c.source, c.receiver, c.heights, bad, "s", "s.glb"), Error);
    bad.sourceWeights = {1.0, 2.0};
    EXPECT_THROW(suggestOnScene(c.scene, c.source, c.receiver, c.heights, bad, "s", "s.glb"), Error);
}
