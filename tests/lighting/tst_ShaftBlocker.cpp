// The shadow proofs of the lights' fast path (lighting/src/lights/ShaftBlocker.h): a triangle or a
// fused convex quadrilateral blocks a whole shaft only when every segment of it crosses, checked
// here against dense samples of the shaft's segments by the contract's own test.
#include <algorithm>
#include <array>
#include <initializer_list>
#include <random>
#include <span>

#include <gtest/gtest.h>

#include "lights/EdgeNeighbours.h"
#include "lights/ShaftBlocker.h"
#include "visibility/ExactSegment.h"

using namespace sightline;
using namespace sightline::lights;

namespace {

/// Whether `blocked(p, q)` holds for 4,000 segments from random points of conv(`from`) to random
/// points of the box (a brute-force reading of what the proofs claim).
template <typename Blocked>
bool everySampleBlockedBy(const std::vector<glm::dvec3>& from, const std::array<glm::dvec3, 8>& box, unsigned seed, Blocked blocked)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto pointOf = [&](std::span<const glm::dvec3> corners) {
        glm::dvec3 x(0.0);
        double total = 0.0;
        for (const glm::dvec3& corner : corners) {
            const double w = unit(rng);
            x += w * corner, total += w;
        }
        return x / total;
    };
    for (int k = 0; k < 4000; ++k) {
        const glm::dvec3 p = pointOf(from), q = pointOf(box);
        if (!blocked(p, q))
            return false;
    }
    return true;
}

/// ... crossing triangle abc or triangle dcb.
bool everySampleBlocked(const std::vector<glm::dvec3>& from, const std::array<glm::dvec3, 8>& box, const glm::dvec3& a,
                        const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3* d)
{
    return everySampleBlockedBy(from, box, 3, [&](const glm::dvec3& p, const glm::dvec3& q) {
        return segmentCrossesTriangle(p, q, a, b, c) || (d && segmentCrossesTriangle(p, q, *d, c, b));
    });
}

std::array<glm::dvec3, 8> boxCorners(const glm::dvec3& lo, const glm::dvec3& hi)
{
    std::array<glm::dvec3, 8> corners;
    for (int c = 0; c < 8; ++c)
        corners[std::size_t(c)] = {(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
    return corners;
}

/// A wall in z = 0 built of 4 x 3 cells of 1 m (two triangles each, welded), less the cells in
/// `holes` (column + 4 * row): the bands between a wall's openings.
WorldTriangles cellWall(std::initializer_list<int> holes = {})
{
    WorldTriangles wall;
    for (int row = 0; row < 3; ++row)
        for (int column = 0; column < 4; ++column) {
            if (std::find(holes.begin(), holes.end(), column + 4 * row) != holes.end())
                continue;
            const float x = float(column) - 2.0f, y = float(row);
            const glm::vec3 p00(x, y, 0), p10(x + 1, y, 0), p01(x, y + 1, 0), p11(x + 1, y + 1, 0);
            for (const glm::vec3& v : {p00, p10, p11, p00, p11, p01})
                wall.vertices.push_back(v);
            wall.instanceOf.insert(wall.instanceOf.end(), 2, 0u);
        }
    return wall;
}

/// ... crossing some triangle of `wall`.
bool everySampleBlockedByWall(const std::vector<glm::dvec3>& from, const std::array<glm::dvec3, 8>& box, const WorldTriangles& wall)
{
    return everySampleBlockedBy(from, box, 5, [&](const glm::dvec3& p, const glm::dvec3& q) {
        for (std::size_t t = 0; t < wall.size(); ++t)
            if (segmentCrossesTriangle(p, q, glm::dvec3(wall.vertices[3 * t]), glm::dvec3(wall.vertices[3 * t + 1]),
                                       glm::dvec3(wall.vertices[3 * t + 2])))
                return true;
        return false;
    });
}

} // namespace

TEST(ShaftBlocker, ATriangleCoveringTheShaftBlocksItAndOneThatDoesNotDoesNot)
{
    const std::vector<glm::dvec3> light = {{0.0, 2.0, -2.0}};
    const auto box = boxCorners({-0.3, 0.0, 1.0}, {0.3, 0.2, 1.5});
    const glm::dvec3 a(-3, -1, 0), b(3, -1, 0), c(0, 4, 0);   // a big triangle in z = 0
    EXPECT_TRUE(triangleBlocksShaft(a, b, c, light, box));
    EXPECT_TRUE(everySampleBlocked(light, box, a, b, c, nullptr));
    const glm::dvec3 small(0.1, 0.5, 0);   // one that covers only part of the shaft
    EXPECT_FALSE(triangleBlocksShaft(a, b, small, light, box));
    EXPECT_FALSE(everySampleBlocked(light, box, a, b, small, nullptr));
    // A box reaching back through the triangle's plane is not separated from the light.
    EXPECT_FALSE(triangleBlocksShaft(a, b, c, light, boxCorners({-0.3, 0.0, -0.1}, {0.3, 0.2, 1.5})));
}

TEST(ShaftBlocker, AConvexQuadOfTwoCoplanarTrianglesBlocksWhereNeitherAloneDoes)
{
    // The quad x, y in [-1, 1] at z = 0, split along its diagonal from (-1, -1) to (1, 1).
    const glm::dvec3 a(1, -1, 0), b(-1, -1, 0), c(1, 1, 0), d(-1, 1, 0);   // (a, b, c) and (d, c, b)
    const std::vector<glm::dvec3> light = {{-0.2, -0.2, -1.0}, {0.2, -0.2, -1.0}, {-0.2, 0.2, -1.0}, {0.2, 0.2, -1.0}};
    const auto box = boxCorners({-0.3, -0.3, 1.0}, {0.3, 0.3, 1.2});
    EXPECT_FALSE(triangleBlocksShaft(a, b, c, light, box));
    EXPECT_FALSE(triangleBlocksShaft(d, c, b, light, box));
    EXPECT_TRUE(quadBlocksShaft(a, b, c, d, light, box));
    EXPECT_TRUE(everySampleBlocked(light, box, a, b, c, &d));
    // Not convex (d pulled inside across the diagonal's far side): refused, and indeed leaky.
    const glm::dvec3 dent(0.1, 0.1, 0.0);
    EXPECT_FALSE(quadBlocksShaft(a, b, c, dent, light, box));
    // Not exactly coplanar: refused.
    EXPECT_FALSE(quadBlocksShaft(a, b, c, glm::dvec3(-1, 1, 1e-9), light, box));
}

TEST(ShaftBlocker, ParallelSegmentsOfADirectionalLight)
{
    const auto box = boxCorners({-0.3, 0.0, -0.3}, {0.3, 0.1, 0.3});
    std::array<glm::dvec3, 8> ends;
    for (std::size_t k = 0; k < 8; ++k)
        ends[k] = box[k] + glm::dvec3(0.5, 50.0, 0.0);   // towards the sun, far above
    const glm::dvec3 a(-5, 3, -5), b(5, 3, -5), c(0, 3, 8);   // a roof triangle
    EXPECT_TRUE(triangleBlocksParallel(a, b, c, box, ends));
    EXPECT_FALSE(triangleBlocksParallel(a, b, glm::dvec3(0, 3, -4), box, ends));
}

TEST(ShaftBlocker, ACoplanarRegionOfManyTrianglesBlocksWhereNoTwoDo)
{
    // An area light in front of the wall's middle, a tile behind it: the shaft crosses six cells.
    const std::vector<glm::dvec3> light = {{-0.4, 1.1, -1.0}, {0.4, 1.1, -1.0}, {-0.4, 1.9, -1.0}, {0.4, 1.9, -1.0}};
    const auto box = boxCorners({-0.6, 0.7, 1.0}, {0.6, 2.3, 1.1});
    const WorldTriangles wall = cellWall();
    const auto neighbours = edgeNeighbours(wall);
    const std::int64_t middle = 2 * (2 + 4 * 1);   // a triangle of the cell (0..1, 1..2)
    EXPECT_TRUE(coplanarRegionBlocksShaft(wall, neighbours, middle, light, box));
    EXPECT_TRUE(everySampleBlockedByWall(light, box, wall));
    const glm::dvec3 a(wall.vertices[3 * middle]), b(wall.vertices[3 * middle + 1]), c(wall.vertices[3 * middle + 2]);
    EXPECT_FALSE(triangleBlocksShaft(a, b, c, light, box));

    // A window in the shaft's path: refused, and indeed leaky; one outside it changes nothing.
    const WorldTriangles window = cellWall({1 + 4 * 1});   // the cell (-1..0, 1..2)
    const std::int64_t seed = 2 * (1 + 4 * 1);              // now the first triangle of the cell (0..1, 1..2)
    EXPECT_FALSE(coplanarRegionBlocksShaft(window, edgeNeighbours(window), seed, light, box));
    EXPECT_FALSE(everySampleBlockedByWall(light, box, window));
    const WorldTriangles aside = cellWall({3 + 4 * 2});   // the top right cell
    EXPECT_TRUE(coplanarRegionBlocksShaft(aside, edgeNeighbours(aside), middle, light, box));

    // A shaft running past the wall's edge: refused.
    const auto beside = boxCorners({3.6, 0.7, 1.0}, {4.6, 2.3, 1.1});
    EXPECT_FALSE(coplanarRegionBlocksShaft(wall, neighbours, middle, light, beside));
    EXPECT_FALSE(everySampleBlockedByWall(light, beside, wall));

    // A triangle folded back over the window's edge (on the same side as the cell it shares the
    // edge with) does not close the window: a shaft through the window's side is refused.
    WorldTriangles folded = cellWall({1 + 4 * 1});
    for (const glm::vec3& v : {glm::vec3(0, 1, 0), glm::vec3(0, 2, 0), glm::vec3(2, 1.5f, 0)})
        folded.vertices.push_back(v);
    folded.instanceOf.push_back(0);
    const std::vector<glm::dvec3> narrow = {{-0.15, 1.35, -1.0}, {0.25, 1.35, -1.0}, {-0.15, 1.65, -1.0}, {0.25, 1.65, -1.0}};
    const auto behind = boxCorners({-0.25, 1.25, 1.0}, {0.35, 1.75, 1.02});
    EXPECT_FALSE(coplanarRegionBlocksShaft(folded, edgeNeighbours(folded), seed, narrow, behind));
    EXPECT_FALSE(everySampleBlockedByWall(narrow, behind, folded));

    // A cell not exactly in the plane is not joined: its gap leaves the region open.
    WorldTriangles bent = cellWall();
    for (std::size_t k = 0; k < 6; ++k)
        bent.vertices[3 * 2 * (1 + 4 * 1) + k].z += 1e-4f;   // the cell (-1..0, 1..2), both triangles
    EXPECT_FALSE(coplanarRegionBlocksShaft(bent, edgeNeighbours(bent), middle, light, box));
}
