#pragma once
// A proof that one triangle shadows a whole tile of points from a light (Barczak's "not lit"
// class, proved rather than read off a shadow map).
//
// Let A be the light's convex extent (a point, or an area light's rectangle) and B the tile's box.
// If a plane separates A from B strictly, every segment from A to B crosses it, and the set of
// crossings is conv(A ∪ B) ∩ plane: the convex hull of where the segments between the corners of
// A and the corners of B cross it (the plane cuts no edge within A or within B). A triangle in that
// plane holding every corner crossing holds every crossing, so it blocks every segment from A to
// B. The corner segments are judged by the contract's own test (segmentCrossesTriangle), and the
// separation is asked to exceed kSeparationMetres, so no crossing lies near a segment's end.
//
// Two triangles sharing an edge, exactly coplanar and forming a convex quadrilateral (a wall's
// face between its openings, split along a diagonal), block together: the crossings' hull lies in
// the quadrilateral, which the two cover (their shared edge inclusive in both, as the contract's
// test has it), so every corner segment crossing one of the two suffices.
//
// Beyond two: the exactly coplanar triangles joined across edges around the first (a wall built
// of bands between its windows) block together when their union U covers K, the crossings' hull.
// U is the set of those triangles that reach K's bounding box; an edge shared by two of them lying
// on opposite sides of it is inside U, every other edge is on U's boundary. If no boundary edge
// meets K and a point inside K lies inside one of them, K lies in U: the interior of K, less finitely
// many vertices, is connected and meets U, and U has no boundary there, so U holds all of it.
// Where rounding could misjudge an edge or a side, the answer is no, or the miss lies within
// rounding of an edge: a tie.
//
// A directional light's segments are parallel: from each point x to x - d L. Their crossings are
// the parallel projection of B, the hull of its corners' projections: the same test with the
// corner segments (c, c - d L).

#include <array>
#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline::lights {

inline constexpr double kSeparationMetres = 1e-6;

/// Whether triangle (a, b, c) blocks every segment from conv(`from`) to conv(`to`), by the argument
/// above. False proves nothing.
bool triangleBlocksShaft(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::span<const glm::dvec3> from,
                         std::span<const glm::dvec3> to);

/// The same for the convex quadrilateral of two exactly coplanar triangles sharing edge (b, c):
/// (a, b, c) and (d, c, b) in either winding. False when they are not such a pair.
bool quadBlocksShaft(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d,
                     std::span<const glm::dvec3> from, std::span<const glm::dvec3> to);

/// The same for the exactly coplanar triangles joined across edges (`neighbours`, EdgeNeighbours.h)
/// around triangle `seed`, by the argument above.
bool coplanarRegionBlocksShaft(const WorldTriangles& triangles, std::span<const std::array<std::int64_t, 3>> neighbours,
                               std::int64_t seed, std::span<const glm::dvec3> from, std::span<const glm::dvec3> to);

/// The same for parallel segments starts[k] -> ends[k] (a directional light's, from a box's corners).
bool triangleBlocksParallel(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::span<const glm::dvec3> starts,
                            std::span<const glm::dvec3> ends);

} // namespace sightline::lights
