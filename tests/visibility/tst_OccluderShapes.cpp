// The plane geometry behind occluder suggestions (visibility/suggest/), each against a brute
// force or a known answer.
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "visibility/suggest/ConvexHull2.h"
#include "visibility/suggest/ShareTrimming.h"

using namespace sightline::suggest;

namespace {

std::vector<Point2> randomPoints(unsigned seed, int count, double spread = 1.0)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0.0, spread);
    std::vector<Point2> points;
    for (int i = 0; i < count; ++i)
        points.push_back({gauss(rng), 0.3 * gauss(rng) + 0.5 * gauss(rng) * (i % 3)});
    return points;
}

/// Brute force: the smallest box over 36,000 orientations.
double bruteMinRectArea(const std::vector<Point2>& points)
{
    double best = 1e300;
    for (int k = 0; k < 36000; ++k) {
        const double a = 0.5 * std::numbers::pi * k / 36000;
        best = std::min(best, boundingRect(points, {std::cos(a), std::sin(a)}).area());
    }
    return best;
}

} // namespace

TEST(ConvexHull2, HoldsEveryPointAndEveryVertexIsExtreme)
{
    for (unsigned seed = 1; seed <= 20; ++seed) {
        const std::vector<Point2> points = randomPoints(seed, 50 + 37 * int(seed));
        const std::vector<Point2> hull = convexHull(points);
        ASSERT_GE(hull.size(), 3u);
        EXPECT_GT(polygonArea(hull), 0.0) << "counter-clockwise";
        for (const Point2& p : points)
            EXPECT_TRUE(insideConvex(hull, p, -1e-12)) << "seed " << seed;
        // Each vertex is strictly outside the hull of the others (no collinear or inner vertex).
        for (std::size_t v = 0; v < hull.size(); ++v) {
            std::vector<Point2> others = hull;
            others.erase(others.begin() + std::ptrdiff_t(v));
            EXPECT_FALSE(insideConvex(convexHull(others), hull[v], -1e-12)) << "seed " << seed << " vertex " << v;
        }
    }
}

TEST(ConvexHull2, DegenerateInputsGiveFewerThanThreeVertices)
{
    EXPECT_EQ(convexHull({{1, 2}, {1, 2}, {1, 2}}).size(), 1u);
    const std::vector<Point2> line = convexHull({{0, 0}, {1, 1}, {2, 2}, {0.5, 0.5}});
    ASSERT_EQ(line.size(), 2u);
    EXPECT_EQ(line[0], Point2(0, 0));
    EXPECT_EQ(line[1], Point2(2, 2));
    const Rect2 rect = minAreaRect(line);
    EXPECT_NEAR(rect.area(), 0.0, 1e-12);
    EXPECT_NEAR(2.0 * std::max(rect.halfWidth, rect.halfHeight), std::sqrt(8.0), 1e-12);
}

TEST(ConvexHull2, MinAreaRectMatchesABruteForceOverOrientations)
{
    for (unsigned seed = 1; seed <= 12; ++seed) {
        const std::vector<Point2> points = randomPoints(seed, 200);
        const std::vector<Point2> hull = convexHull(points);
        const Rect2 rect = minAreaRect(hull);
        const double brute = bruteMinRectArea(points);
        EXPECT_LE(rect.area(), brute * (1.0 + 1e-9)) << "seed " << seed;
        EXPECT_GE(rect.area(), brute * (1.0 - 1e-3)) << "seed " << seed;   // the brute force's angle step
        const auto corners = rect.corners();
        for (const Point2& p : points)
            EXPECT_TRUE(insideConvex(corners, p, -1e-9)) << "seed " << seed;
    }
}

TEST(ConvexHull2, GrownPolygonPutsEveryPointAtLeastTheMarginInside)
{
    for (unsigned seed = 1; seed <= 10; ++seed) {
        const std::vector<Point2> points = randomPoints(seed, 300);
        const std::vector<Point2> hull = convexHull(points);
        const double margin = 1e-3 * seed;
        const std::vector<Point2> grown = grownPolygon(hull, margin);
        for (const Point2& p : points)
            EXPECT_TRUE(insideConvex(grown, p, margin * (1.0 - 1e-9))) << "seed " << seed;
        // Never much more than the strip along the perimeter plus the corners.
        double perimeter = 0.0;
        for (std::size_t i = 0; i < hull.size(); ++i)
            perimeter += glm::length(hull[(i + 1) % hull.size()] - hull[i]);
        EXPECT_LE(polygonArea(grown) - polygonArea(hull), margin * perimeter + 4.0 * margin * margin * double(hull.size()));
    }
}

TEST(ConvexHull2, SharpCornersAreCutSquareAndStayAMarginOut)
{
    // Needles: corners of 0.01 to 5 degrees, where a miter would reach metres out.
    for (const double degrees : {0.01, 0.5, 5.0}) {
        const double half = 0.5 * degrees * std::numbers::pi / 180.0;
        const std::vector<Point2> needle{{0.0, 0.0}, {10.0, -10.0 * std::tan(half)}, {10.0, 10.0 * std::tan(half)}};
        const std::vector<Point2> hull = convexHull(needle);
        const double margin = 1e-3;
        const std::vector<Point2> grown = grownPolygon(hull, margin);
        EXPECT_GT(polygonArea(grown), 0.0);
        for (const Point2& p : hull)
            EXPECT_TRUE(insideConvex(grown, p, margin * (1.0 - 1e-6))) << degrees;
        for (const Point2& q : grown)   // no vertex strays far: at most a few margins from the needle
            EXPECT_LT(q.x, 10.0 + 4.0 * margin) << degrees;
        EXPECT_GT(grown.front().x, -4.0 * margin) << degrees;
    }
}

TEST(ShareTrimming, LeavesOutTheOutliersAndKeepsWhatWasAsked)
{
    // 2,000 points in the unit square and 40 scattered far out: keeping 2,000 drops the outliers.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Point2> points;
    for (int i = 0; i < 2000; ++i)
        points.push_back({unit(rng), unit(rng)});
    for (int i = 0; i < 40; ++i) {
        const double a = 2.0 * std::numbers::pi * unit(rng);
        points.push_back({0.5 + (3.0 + 5.0 * unit(rng)) * std::cos(a), 0.5 + (3.0 + 5.0 * unit(rng)) * std::sin(a)});
    }
    for (const int directions : {4, 64}) {
        const std::vector<char> keep = trimToShare(points, 2000, evenDirections(directions));
        std::vector<Point2> kept;
        for (std::size_t i = 0; i < points.size(); ++i)
            if (keep[i])
                kept.push_back(points[i]);
        EXPECT_GE(kept.size(), 2000u);
        EXPECT_LE(polygonArea(convexHull(kept)), 1.0) << directions << " directions";
    }
}

TEST(ShareTrimming, KeepsAtLeastTheShareOnEveryLayout)
{
    for (unsigned seed = 1; seed <= 8; ++seed) {
        const std::vector<Point2> points = randomPoints(seed, 5000);
        const std::vector<Point2> full = convexHull(points);
        for (const std::size_t keep : {std::size_t(1), std::size_t(2500), std::size_t(4750), std::size_t(4999)}) {
            const std::vector<char> flags = trimToShare(points, keep, evenDirections(64));
            std::vector<Point2> kept;
            for (std::size_t i = 0; i < points.size(); ++i)
                if (flags[i])
                    kept.push_back(points[i]);
            EXPECT_GE(kept.size(), keep) << "seed " << seed;
            EXPECT_LE(polygonArea(convexHull(kept)), polygonArea(full)) << "seed " << seed;
        }
    }
}
