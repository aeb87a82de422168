// Where a segment first meets the scene (the editor's ray marks) against closed forms: walls at
// known planes, hit in order, ends excluded.
#include <random>

#include <gtest/gtest.h>

#include "visibility/SegmentHits.h"

using namespace sightline;

namespace {

/// Walls: the squares x = c for each c, y and z in [-5, 5], two triangles each.
WorldTriangles wallsAt(const std::vector<float>& planes)
{
    WorldTriangles t;
    for (float c : planes) {
        const glm::vec3 a(c, -5, -5), b(c, 5, -5), d(c, 5, 5), e(c, -5, 5);
        for (const glm::vec3& v : {a, b, d, a, d, e})
            t.vertices.push_back(v);
        t.instanceOf.insert(t.instanceOf.end(), 2, 0u);
    }
    return t;
}

} // namespace

TEST(SegmentHits, TheNearestWallAlongARandomSegmentIsItsFirstHit)
{
    const SegmentHitCaster caster(wallsAt({3.0f, 1.0f, 2.0f}));   // unsorted on purpose
    std::mt19937 random(7);
    std::uniform_real_distribution<double> yz(-4.0, 4.0), start(-1.0, 0.5), end(3.5, 6.0);
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 from(start(random), yz(random), yz(random)), to(end(random), yz(random), yz(random));
        const double expected = (1.0 - from.x) / (to.x - from.x);   // the wall at x = 1 comes first
        EXPECT_NEAR(caster.firstHit(from, to), expected, 1e-5) << k;
        // Backwards, the wall at x = 3 is the first.
        EXPECT_NEAR(caster.firstHit(to, from), (to.x - 3.0) / (to.x - from.x), 1e-5) << k;
    }
}

TEST(SegmentHits, MissesAndTheSegmentsOwnEndsAreNoHit)
{
    const SegmentHitCaster caster(wallsAt({1.0f}));
    EXPECT_EQ(caster.firstHit({-1, 0, 0}, {0.5, 0, 0}), 1.0f);   // stops short of the wall
    EXPECT_EQ(caster.firstHit({-1, 6, 0}, {2, 6, 0}), 1.0f);     // passes above it
    EXPECT_EQ(caster.firstHit({1, 0, 0}, {3, 0, 0}), 1.0f);      // starts on it (a patch on a wall)
    EXPECT_EQ(caster.firstHit({-1, 0, 0}, {1, 0, 0}), 1.0f);     // ends on it
    EXPECT_EQ(caster.firstHit({0, 0, 0}, {0, 0, 0}), 1.0f);      // no length
    const SegmentHitCaster empty(WorldTriangles{});
    EXPECT_EQ(empty.firstHit({-1, 0, 0}, {3, 0, 0}), 1.0f);
}
