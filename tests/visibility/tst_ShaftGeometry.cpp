// The shaft's hull: every point of every patch-to-patch segment is inside; far points are not.
#include <random>

#include <gtest/gtest.h>

#include "TestScenes.h"
#include "visibility/ShaftGeometry.h"

using namespace sightline;
using namespace sightline::test;

TEST(ShaftHull, BoxBetweenFacingSquaresHasSixFaces)
{
    const ShaftHull hull(xyPatch(0, 4, 4), xyPatch(2, 4, 4));
    EXPECT_EQ(hull.planeCount(), 6u);
    EXPECT_FALSE(hull.excludesBox({0.2f, 0.2f, 0.5f}, {0.4f, 0.4f, 0.6f}));
    EXPECT_TRUE(hull.excludesBox({1.5f, 0.0f, 0.5f}, {2.0f, 1.0f, 1.5f}));     // beside the shaft
    EXPECT_TRUE(hull.excludes({0.5f, 0.5f, -1.0f}, {0.6f, 0.5f, -1.0f}, {0.5f, 0.6f, -0.5f}));   // behind the source
    EXPECT_FALSE(hull.excludes({-5.0f, 0.5f, 1.0f}, {5.0f, 0.5f, 1.0f}, {0.0f, 0.6f, 1.0f}));    // across it
}

TEST(ShaftHull, NeverExcludesAPointOnASegment)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int checked = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        const RandomCase c = randomCase(seed);
        if (!c.valid())
            continue;
        ++checked;
        const ShaftHull hull(c.source, c.receiver);
        EXPECT_GE(hull.planeCount(), 5u);
        for (int k = 0; k < 500; ++k) {
            const glm::dvec3 s = c.source.corner + unit(rng) * c.source.u + unit(rng) * c.source.v;
            const glm::dvec3 r = c.receiver.corner + unit(rng) * c.receiver.u + unit(rng) * c.receiver.v;
            const glm::dvec3 p = s + unit(rng) * (r - s);
            ASSERT_FALSE(hull.excludes(&p, 1)) << "seed " << seed;
            // Well beyond the source, away from the receiver, is outside.
            const glm::dvec3 behind = s + 2.0 * (s - r);
            ASSERT_TRUE(hull.excludes(&behind, 1)) << "seed " << seed;
        }
    }
    EXPECT_GE(checked, 30);
}

TEST(ClipPolygon, KeepsAPolygonWhollyInsideAndCutsOneThatCrosses)
{
    // Wholly on the kept side (z > 0.25): unchanged, vertex for vertex.
    ClippedPolygon inside;
    inside.vertices[0] = {0.1, 0.2, 0.3};
    inside.vertices[1] = {1.7, -0.4, 0.9};
    inside.vertices[2] = {-2.3, 5.1, 0.25000000000001};
    inside.count = 3;
    const ClippedPolygon before = inside;
    clipPolygon(inside, {0.0, 0.0, 1.0}, 0.25);
    ASSERT_EQ(inside.count, 3);
    for (int i = 0; i < 3; ++i)
        EXPECT_EQ(inside.vertices[std::size_t(i)], before.vertices[std::size_t(i)]);

    // A vertex on the plane counts as outside; one below it is cut away: the triangle
    // (0,0,1) (2,0,1) (0,0,-1) against z > 0 keeps the quad with the cuts at (0,0,0) and (1,0,0).
    ClippedPolygon crossing;
    crossing.vertices[0] = {0.0, 0.0, 1.0};
    crossing.vertices[1] = {2.0, 0.0, 1.0};
    crossing.vertices[2] = {0.0, 0.0, -1.0};
    crossing.count = 3;
    clipPolygon(crossing, {0.0, 0.0, 1.0}, 0.0);
    ASSERT_EQ(crossing.count, 4);
    EXPECT_EQ(crossing.vertices[0], glm::dvec3(0.0, 0.0, 1.0));
    EXPECT_EQ(crossing.vertices[1], glm::dvec3(2.0, 0.0, 1.0));
    EXPECT_EQ(crossing.vertices[2], glm::dvec3(1.0, 0.0, 0.0));
    EXPECT_EQ(crossing.vertices[3], glm::dvec3(0.0, 0.0, 0.0));
}
