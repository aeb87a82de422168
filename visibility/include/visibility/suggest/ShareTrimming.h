#pragma once
// Which points to leave out so that a small convex shape holds the rest: the choice behind an
// occluder that blocks only a share of the rays.
//
// The smallest convex polygon holding at least k of n points is a hard problem in general
// (O(n^3 k) exact algorithms). This is a greedy approximation on the polygon's support lines:
// the shape is the intersection of half-planes {x : d . x <= h_d} over fixed directions d; each
// step pulls in the one support line whose next band of points costs the fewest points per square
// metre saved, until the budget of points to leave out is spent. With the four sides of a box as
// the directions it trims a rectangle; with many directions, a convex polygon. Whatever it
// chooses, the caller's shape is built from the points kept (their exact hull or box), so every
// kept point is inside: the result is a valid answer, only perhaps not the smallest.

#include <cstddef>
#include <span>
#include <vector>

#include "visibility/suggest/ConvexHull2.h"

namespace sightline::suggest {

/// `count` unit directions spread evenly over a full turn, the first at `angle` radians.
std::vector<Point2> evenDirections(int count, double angle = 0.0);

/// Flags the points to keep (1) so that at least `keep` are kept, leaving out at most
/// points.size() - keep by pulling the support lines of `directions` inward. keep <= points.size().
std::vector<char> trimToShare(std::span<const Point2> points, std::size_t keep, std::span<const Point2> directions);

/// The same with a weight per point (>= 0, finite): the points kept weigh at least `keepWeight`
/// (at most the sum of the weights), and each step leaves out the band that costs the least weight
/// per square metre saved.
std::vector<char> trimToWeight(std::span<const Point2> points, std::span<const double> weights, double keepWeight,
                               std::span<const Point2> directions);

} // namespace sightline::suggest
