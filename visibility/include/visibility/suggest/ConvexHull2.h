#pragma once
// Plane geometry for occluder suggestions: convex hulls, the smallest enclosing rectangle and
// polygons grown by a margin, in double precision over points given in a plane's 2D coordinates.

#include <array>
#include <span>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace sightline::suggest {

using Point2 = glm::dvec2;

/// Andrew's monotone chain: the hull counter-clockwise, without repeated or collinear vertices.
/// Fewer than three vertices when the points are all equal (one) or collinear (the two ends).
std::vector<Point2> convexHull(std::vector<Point2> points);

/// Area of a simple polygon, positive when counter-clockwise.
double polygonArea(std::span<const Point2> polygon);

/// A rectangle free in the plane: centre, the unit direction of its first side, half extents.
struct Rect2 {
    Point2 centre{0.0};
    Point2 axis{1.0, 0.0};
    double halfWidth = 0.0;    ///< along axis
    double halfHeight = 0.0;   ///< along axis turned +90 degrees
    double area() const { return 4.0 * halfWidth * halfHeight; }
    /// Counter-clockwise, starting at centre - w axis - h perp.
    std::array<Point2, 4> corners() const;
};

/// The smallest box with a side along `axis` (unit) that holds every point.
Rect2 boundingRect(std::span<const Point2> points, Point2 axis);

/// The smallest-area rectangle enclosing a convex polygon: one of its sides lies along an edge of
/// the hull (Freeman & Shapira 1975), so trying each edge's direction finds it. A hull of one or
/// two points gives a rectangle of zero area along them.
Rect2 minAreaRect(std::span<const Point2> hull);

/// The convex polygon (counter-clockwise, at least three vertices) with every edge moved outward
/// by `margin` and neighbouring edges met again (a corner sharper than about 11 degrees is cut
/// square instead, two vertices for one): every point of the original lies at least `margin`
/// inside the result.
std::vector<Point2> grownPolygon(std::span<const Point2> convex, double margin);

/// True when `p` lies inside the counter-clockwise convex polygon, at least `margin` from each edge.
bool insideConvex(std::span<const Point2> convex, Point2 p, double margin = 0.0);

} // namespace sightline::suggest
