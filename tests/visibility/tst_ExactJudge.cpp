// The judges themselves on known answers: the tests' exact brute force (ExactJudge.h) and the
// contract's double test that the reference uses (ExactSegment.h).

#include <random>

#include <gtest/gtest.h>

#include "ExactJudge.h"
#include "TestScenes.h"
#include "visibility/ExactSegment.h"

using namespace sightline;
using namespace sightline::test;

namespace {

/// One triangle in the plane z = 1: (0, 0), (1, 0), (0, 1).
WorldTriangles oneTriangle(double offset = 0.0)
{
    WorldTriangles t;
    t.vertices = {glm::vec3(glm::dvec3(0, 0, 1) + offset), glm::vec3(glm::dvec3(1, 0, 1) + offset),
                  glm::vec3(glm::dvec3(0, 1, 1) + offset)};
    t.instanceOf = {0};
    return t;
}

/// A 1x1 source at z = 0 and receiver at z = 2 with one sample each, at the given points.
struct Pair {
    Patch source, receiver;
};
Pair pairThrough(const glm::dvec3& sourceSample, const glm::dvec3& receiverSample)
{
    Pair p;
    p.source = xyPatch(sourceSample.z, 1, 1, 1e-3);
    p.source.corner = sourceSample - glm::dvec3(0.5e-3, 0.5e-3, 0.0);
    p.receiver = xyPatch(receiverSample.z, 1, 1, 1e-3);
    p.receiver.corner = receiverSample - glm::dvec3(0.5e-3, 0.5e-3, 0.0);
    return p;
}

RayKind kindOf(const WorldTriangles& t, const glm::dvec3& s, const glm::dvec3& r)
{
    const Pair p = pairThrough(s, r);
    return ExactJudge(t, p.source, p.receiver).ray(0, 0);
}

} // namespace

TEST(ExactJudge, ClassifiesRaysByTheirDistanceToEdgesAndEnds)
{
    const WorldTriangles t = oneTriangle();
    // Straight through the interior, far from every edge.
    EXPECT_EQ(kindOf(t, {0.25, 0.25, 0}, {0.25, 0.25, 2}), RayKind::Blocked);
    // Beside the triangle by 1 mm: free.
    EXPECT_EQ(kindOf(t, {-1e-3, 0.5, 0}, {-1e-3, 0.5, 2}), RayKind::Free);
    // 1e-6 m inside or outside the edge x = 0: an edge tie either way.
    EXPECT_EQ(kindOf(t, {1e-6, 0.5, 0}, {1e-6, 0.5, 2}), RayKind::EdgeTie);
    EXPECT_EQ(kindOf(t, {-1e-6, 0.5, 0}, {-1e-6, 0.5, 2}), RayKind::EdgeTie);
    // 2e-5 m from the edge is beyond the tie distance.
    EXPECT_EQ(kindOf(t, {2e-5, 0.5, 0}, {2e-5, 0.5, 2}), RayKind::Blocked);
    EXPECT_EQ(kindOf(t, {-2e-5, 0.5, 0}, {-2e-5, 0.5, 2}), RayKind::Free);
    // Ending 1e-6 m short of the triangle, or 1e-6 m past it: end ties.
    EXPECT_EQ(kindOf(t, {0.25, 0.25, 1 - 1e-6}, {0.25, 0.25, 3}), RayKind::EndTie);
    EXPECT_EQ(kindOf(t, {0.25, 0.25, 1 + 1e-6}, {0.25, 0.25, 3}), RayKind::EndTie);
    // Ending 1 mm short: free.
    EXPECT_EQ(kindOf(t, {0.25, 0.25, 1 + 1e-3}, {0.25, 0.25, 3}), RayKind::Free);
    // In the triangle's plane, beside it by 1 cm: free; across it: a tie (it touches the edges).
    EXPECT_EQ(kindOf(t, {-0.5, -0.01, 1}, {1.5, -0.01, 1}), RayKind::Free);
    EXPECT_EQ(kindOf(t, {-0.5, 0.25, 1}, {1.5, 0.25, 1}), RayKind::EdgeTie);
}

TEST(ExactJudge, IsAsExactAHundredKilometresOut)
{
    // The same rays, the scene and the patches moved 1e5 m (a power of two apart in float, so the
    // triangle's vertices stay where they were relative to each other).
    const double offset = 131072.0;
    const WorldTriangles t = oneTriangle(offset);
    const glm::dvec3 o(offset);
    EXPECT_EQ(kindOf(t, o + glm::dvec3(0.25, 0.25, 0), o + glm::dvec3(0.25, 0.25, 2)), RayKind::Blocked);
    EXPECT_EQ(kindOf(t, o + glm::dvec3(2e-5, 0.5, 0), o + glm::dvec3(2e-5, 0.5, 2)), RayKind::Blocked);
    EXPECT_EQ(kindOf(t, o + glm::dvec3(-2e-5, 0.5, 0), o + glm::dvec3(-2e-5, 0.5, 2)), RayKind::Free);
    EXPECT_EQ(kindOf(t, o + glm::dvec3(1e-6, 0.5, 0), o + glm::dvec3(1e-6, 0.5, 2)), RayKind::EdgeTie);
}

TEST(ExactJudge, ABlockedRayStaysBlockedWhateverTiesAnotherTriangle)
{
    // A second triangle whose edge the ray grazes does not make a clearly blocked ray a tie.
    WorldTriangles t = oneTriangle();
    t.vertices.insert(t.vertices.end(), {glm::vec3(0.25f, 0.25f, 1.5f), glm::vec3(1, 0.25f, 1.5f), glm::vec3(1, 1, 1.5f)});
    t.instanceOf.push_back(0);
    EXPECT_EQ(kindOf(t, {0.25, 0.25, 0}, {0.25, 0.25, 2}), RayKind::Blocked);
    // Without the first, the grazing is all there is.
    WorldTriangles second;
    second.vertices.assign(t.vertices.begin() + 3, t.vertices.end());
    second.instanceOf = {0};
    EXPECT_EQ(kindOf(second, {0.25, 0.25, 0}, {0.25, 0.25, 2}), RayKind::EdgeTie);
}

TEST(ExactSegment, AgreesWithTheJudgeOnEveryRayThatIsNotATie)
{
    // Random segments against random triangles near them, at the origin and 10 km out.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int compared = 0, ties = 0;
    for (double offset : {0.0, 1e4}) {
        for (int n = 0; n < 20000; ++n) {
            const glm::dvec3 o(offset, -offset, 0.5 * offset);
            const glm::dvec3 a = o + glm::dvec3(unit(rng), unit(rng), unit(rng));
            const glm::dvec3 b = a + 0.3 * glm::dvec3(unit(rng), unit(rng), unit(rng));
            const glm::dvec3 c = a + 0.3 * glm::dvec3(unit(rng), unit(rng), unit(rng));
            const glm::dvec3 fa{glm::vec3(a)}, fb{glm::vec3(b)}, fc{glm::vec3(c)};   // float input
            const glm::dvec3 p = o + glm::dvec3(unit(rng), unit(rng), unit(rng));
            const glm::dvec3 q = o + glm::dvec3(unit(rng), unit(rng), unit(rng));
            const TriangleVerdict v = judgeTriangle(p, q, fa, fb, fc);
            if (v.edgeTie || v.endTie) {
                ++ties;
                continue;
            }
            ++compared;
            ASSERT_EQ(segmentCrossesTriangle(p, q, fa, fb, fc), v.crosses) << "segment " << n << " offset " << offset;
        }
    }
    EXPECT_GT(compared, 39000);
    EXPECT_LT(ties, 1000);
}

TEST(ExactSegment, ASegmentThroughASharedEdgeIsBlockedByOneOfItsTriangles)
{
    // A wall of two triangles, rays exactly through its diagonal: edges are inclusive, and both
    // triangles compute the shared edge's predicate from the same two vertices, so no crack.
    const glm::dvec3 a(0, 0, 1), b(1, 0, 1), c(1, 1, 1), d(0, 1, 1);
    int blocked = 0;
    for (int k = 1; k < 100; ++k) {
        const double x = k / 100.0;
        const glm::dvec3 p(x, x, 0), q(x, x, 2);
        blocked += segmentCrossesTriangle(p, q, a, b, c) || segmentCrossesTriangle(p, q, a, c, d);
    }
    EXPECT_EQ(blocked, 99);
}

TEST(ExactSegment, AWallTouchingTheEndDoesNotBlock)
{
    // The segment ends on the triangle's plane inside it (a patch lying on a wall).
    const glm::dvec3 a(0, 0, 1), b(1, 0, 1), c(0, 1, 1);
    EXPECT_FALSE(segmentCrossesTriangle({0.25, 0.25, 1}, {0.25, 0.25, 3}, a, b, c));
    EXPECT_FALSE(segmentCrossesTriangle({0.25, 0.25, -1}, {0.25, 0.25, 1}, a, b, c));
    EXPECT_TRUE(segmentCrossesTriangle({0.25, 0.25, 1 - 1e-6}, {0.25, 0.25, 3}, a, b, c));
}
