#pragma once
// The portals of a BSP's world tree: the convex polygons where two leaves' volumes touch, rebuilt
// from the tree alone as a compiler does before vis (qbsp's MakeTreePortals). Each node's plane,
// clipped by the planes of its ancestors' portals, is split down the tree until every piece lies
// between two leaves; the level's box, a little enlarged, closes the outside. Windings are in
// double precision; points within kPortalOnPlane of a cutting plane are kept on both sides, so a
// portal can only come out larger than the exact face, never smaller (what vis needs to stay safe).

#include <vector>

#include <glm/vec3.hpp>

#include "visibility/bsp/QuakeBsp.h"

namespace sightline::bsp {

using Winding = std::vector<glm::dvec3>;

/// Quake units: far below a level's detail (1 unit is an inch), far above double rounding at
/// Quake's coordinates (|x| <= 32768).
inline constexpr double kPortalOnPlane = 1e-3;

/// The outside of the level's box, as a portal side.
inline constexpr int kOutside = -1;

struct LeafPortal {
    std::array<int, 2> leaves{};   ///< [0] in front of `plane`, [1] behind; a leaf index or kOutside
    BspPlane plane;                ///< unit normal, pointing into leaves[0]
    Winding winding;               ///< convex, at least 3 points, on `plane`
};

/// Every portal of the world tree with a leaf on at least one side (leaf to leaf, and leaf to
/// the outside of the level's box), in the order the tree makes them.
std::vector<LeafPortal> treePortals(const QuakeBsp& bsp);

/// Which portals a line of sight may cross: both sides non-solid leaves with rows (1..visleafs)
/// and the same contents, as Quake's compilers write them to the .prt file. With `clearLiquids`,
/// water, slime and lava also open onto empty leaves and each other (ericw-tools' transwater).
bool seesThrough(const QuakeBsp& bsp, const LeafPortal& portal, bool clearLiquids);

/// The portals a line of sight may cross (seesThrough), in order.
std::vector<LeafPortal> openPortals(const QuakeBsp& bsp, bool clearLiquids);

/// The PRT1 text vis tools read beside the BSP: visleafs, portal count, then per portal its point
/// count, the two leaves as visleaf indices (leaf - 1), and its points in the level's units. Each
/// winding is written in the order whose plane (vis's PlaneFromWinding) faces the first leaf.
std::string prt1(const QuakeBsp& bsp, const std::vector<LeafPortal>& open);

/// Chops `w` to the side of the plane (n, d) where n.x - d >= -onPlane (the front, points within
/// onPlane of the plane kept). Fewer than three points left: empty.
Winding chopFront(const Winding& w, const glm::dvec3& n, double d, double onPlane);

} // namespace sightline::bsp
