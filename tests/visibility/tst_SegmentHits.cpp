// Where a segment first meets the scene (segmentFirstHit: the editor's ray marks) against closed
// forms: walls at known planes, hit in order, ends excluded.
#include <random>

#include <gtest/gtest.h>

#include "TestScenes.h"
#include "visibility/pvs/FirstHitCaster.h"

using namespace sightline;

namespace {

/// Walls: the squares x = c for each c, y and z in [-5, 5].
Scene wallsAt(const std::vector<float>& planes)
{
    std::vector<Mesh> walls;
    for (float c : planes)
        walls.push_back(test::quad({c, -5.0f, -5.0f}, {0.0f, 10.0f, 0.0f}, {0.0f, 0.0f, 10.0f}, "wall"));
    return test::sceneOf(walls);
}

} // namespace

TEST(SegmentHits, TheNearestWallAlongARandomSegmentIsItsFirstHit)
{
    const pvs::FirstHitCaster caster(wallsAt({3.0f, 1.0f, 2.0f}));   // unsorted on purpose
    std::mt19937 random(7);
    std::uniform_real_distribution<double> yz(-4.0, 4.0), start(-1.0, 0.5), end(3.5, 6.0);
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 from(start(random), yz(random), yz(random)), to(end(random), yz(random), yz(random));
        const double expected = (1.0 - from.x) / (to.x - from.x);   // the wall at x = 1 comes first
        EXPECT_NEAR(segmentFirstHit(caster, from, to), expected, 1e-5) << k;
        // Backwards, the wall at x = 3 is the first.
        EXPECT_NEAR(segmentFirstHit(caster, to, from), (to.x - 3.0) / (to.x - from.x), 1e-5) << k;
    }
}

TEST(SegmentHits, MissesAndTheSegmentsOwnEndsAreNoHit)
{
    const pvs::FirstHitCaster caster(wallsAt({1.0f}));
    EXPECT_EQ(segmentFirstHit(caster, {-1, 0, 0}, {0.5, 0, 0}), 1.0f);   // stops short of the wall
    EXPECT_EQ(segmentFirstHit(caster, {-1, 6, 0}, {2, 6, 0}), 1.0f);     // passes above it
    EXPECT_EQ(segmentFirstHit(caster, {1, 0, 0}, {3, 0, 0}), 1.0f);      // starts on it (a patch on a wall)
    EXPECT_EQ(segmentFirstHit(caster, {-1, 0, 0}, {1, 0, 0}), 1.0f);     // ends on it
    EXPECT_EQ(segmentFirstHit(caster, {0, 0, 0}, {0, 0, 0}), 1.0f);      // no length
    const pvs::FirstHitCaster empty(Scene{});
    EXPECT_EQ(segmentFirstHit(empty, {-1, 0, 0}, {3, 0, 0}), 1.0f);
}
