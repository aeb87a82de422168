#include "visibility/suggest/ConvexHull2.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace sightline::suggest {

namespace {

double cross(Point2 o, Point2 a, Point2 b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

Point2 perp(Point2 axis)
{
    return {-axis.y, axis.x};
}

/// Akl-Toussaint: a point strictly inside the polygon of the extreme points in eight directions
/// is no vertex of the hull, so most of a dense cloud is dropped before the sort. (Rounding can
/// only drop a point within an ulp of that polygon's edge, well inside the hull's own margin.)
void dropInnerPoints(std::vector<Point2>& points)
{
    constexpr double kDirections[8][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
    std::vector<Point2> extremes;
    for (const auto& d : kDirections) {
        const Point2 direction(d[0], d[1]);
        extremes.push_back(*std::max_element(points.begin(), points.end(), [&](Point2 a, Point2 b) {
            return glm::dot(direction, a) < glm::dot(direction, b);
        }));
    }
    const std::vector<Point2> octagon = convexHull(std::move(extremes));
    if (octagon.size() < 3)
        return;
    std::erase_if(points, [&](Point2 p) {
        for (std::size_t i = 0, n = octagon.size(); i < n; ++i)
            if (cross(octagon[i], octagon[(i + 1) % n], p) <= 0.0)
                return false;
        return true;
    });
}

} // namespace

std::vector<Point2> convexHull(std::vector<Point2> points)
{
    if (points.size() > 64)
        dropInnerPoints(points);
    std::sort(points.begin(), points.end(), [](Point2 a, Point2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    points.erase(std::unique(points.begin(), points.end()), points.end());
    if (points.size() < 3)
        return points;
    std::vector<Point2> hull(2 * points.size());
    std::size_t k = 0;
    for (const Point2& p : points) {   // lower chain
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0.0)
            --k;
        hull[k++] = p;
    }
    for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {   // upper chain
        while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0)
            --k;
        hull[k++] = points[i];
    }
    hull.resize(k - 1);   // the last point repeats the first
    return hull;
}

double polygonArea(std::span<const Point2> polygon)
{
    double twice = 0.0;
    for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
        const Point2& a = polygon[i];
        const Point2& b = polygon[(i + 1) % n];
        twice += a.x * b.y - a.y * b.x;
    }
    return 0.5 * twice;
}

std::array<Point2, 4> Rect2::corners() const
{
    const Point2 w = halfWidth * axis;
    const Point2 h = halfHeight * perp(axis);
    return {centre - w - h, centre + w - h, centre + w + h, centre - w + h};
}

Rect2 boundingRect(std::span<const Point2> points, Point2 axis)
{
    assert(!points.empty());
    const Point2 side = perp(axis);
    double lo0 = std::numeric_limits<double>::infinity(), hi0 = -lo0, lo1 = lo0, hi1 = -lo0;
    for (const Point2& p : points) {
        const double s = glm::dot(p, axis), t = glm::dot(p, side);
        lo0 = std::min(lo0, s);
        hi0 = std::max(hi0, s);
        lo1 = std::min(lo1, t);
        hi1 = std::max(hi1, t);
    }
    Rect2 rect;
    rect.axis = axis;
    rect.centre = 0.5 * (lo0 + hi0) * axis + 0.5 * (lo1 + hi1) * side;
    rect.halfWidth = 0.5 * (hi0 - lo0);
    rect.halfHeight = 0.5 * (hi1 - lo1);
    return rect;
}

Rect2 minAreaRect(std::span<const Point2> hull)
{
    assert(!hull.empty());
    if (hull.size() == 1)
        return boundingRect(hull, {1.0, 0.0});
    Rect2 best;
    double bestArea = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0, n = hull.size(); i < n; ++i) {
        const Point2 edge = hull[(i + 1) % n] - hull[i];
        const double length = std::hypot(edge.x, edge.y);
        if (length == 0.0)
            continue;
        const Rect2 rect = boundingRect(hull, edge / length);
        // Ties go to the larger extent along the axis, so a two-point hull lies along its axis.
        if (rect.area() < bestArea) {
            bestArea = rect.area();
            best = rect;
        }
    }
    return best;
}

std::vector<Point2> grownPolygon(std::span<const Point2> convex, double margin)
{
    const std::size_t n = convex.size();
    assert(n >= 3);
    std::vector<Point2> normals(n);   // outward unit normal of edge i -> i + 1
    for (std::size_t i = 0; i < n; ++i) {
        const Point2 edge = convex[(i + 1) % n] - convex[i];
        normals[i] = Point2{edge.y, -edge.x} / std::hypot(edge.x, edge.y);
    }
    std::vector<Point2> grown;
    grown.reserve(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
        // Vertex i joins edges i - 1 and i: the miter moves it along the normals' bisector by
        // margin / cos(half the turn), which puts both edges exactly `margin` out.
        const Point2 p = convex[i], a = normals[(i + n - 1) % n], b = normals[i];
        const double cosine = 0.5 * (1.0 + glm::dot(a, b));   // cos^2 of half the turn
        if (cosine >= 0.01) {
            grown.push_back(p + margin * (a + b) / (2.0 * cosine));
            continue;
        }
        // A corner sharper than about 11 degrees: its miter would reach far out (or, at a hair's
        // width, nowhere useful), so it is cut square by the line `margin` beyond the vertex
        // along the bisector, met by both offset edges.
        const Point2 in = glm::normalize(p - convex[(i + n - 1) % n]), out = glm::normalize(p - convex[(i + 1) % n]);
        const Point2 m = glm::normalize(in + out);   // the bisector, out through the tip (a + b is ~0 here)
        grown.push_back(p + margin * a + in * (margin * (1.0 - glm::dot(a, m)) / glm::dot(in, m)));
        grown.push_back(p + margin * b + out * (margin * (1.0 - glm::dot(b, m)) / glm::dot(out, m)));
    }
    return grown;
}

bool insideConvex(std::span<const Point2> convex, Point2 p, double margin)
{
    for (std::size_t i = 0, n = convex.size(); i < n; ++i) {
        const Point2 a = convex[i], b = convex[(i + 1) % n];
        const double length = glm::length(b - a);
        if (cross(a, b, p) < margin * length)
            return false;
    }
    return true;
}

} // namespace sightline::suggest
