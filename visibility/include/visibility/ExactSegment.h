#pragma once
// docs/design.md §2's blocking rule, made concrete once for every method.
//
// A ray between a source and a receiver sample is blocked when its segment crosses a triangle
// strictly between its ends. "Strictly" needs a number where arithmetic rounds: a crossing closer
// than kEndMarginMetres to an end does not count, so a patch lying on a wall is not blocked by
// that wall. The contract lets ties (rays within 1e-5 m of an edge, or meeting a triangle within
// 1e-5 m of an end) go either way, so any margin well below 1e-5 m and well above rounding is a
// correct reading; 1e-8 m is a thousand times below the tie distance and a hundred times above
// double rounding at the largest coordinates Sightline accepts (1e6 m: 1.2e-10 m).
//
// Methods apply the margin where they work: along the segment (the reference's exact test
// below), or as the perpendicular distance from a patch's plane (the bitmask samplers clip
// triangles to the slab between the planes, kEndMarginMetres inside each): the crossing point of
// a ray whose end lies on the plane is then at least that far from the end, and at most
// kEndMarginMetres / cos(angle to the normal) away, far inside the tie distance for any patch
// pair but the most oblique.

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace sightline {

inline constexpr double kEndMarginMetres = 1e-8;

/// docs/design.md §2's largest accepted coordinate magnitude (after transforms), in metres.
inline constexpr double kMaxCoordinateMetres = 1e6;

/// The contract's test for segments that start at one point p, split in what depends on p and
/// the triangle alone (computed once: the rays of a packet share their receiver end) and what each
/// segment adds (its direction d = q - p: three dot products for the sides, one for the plane).
struct TriangleSeenFrom {
    glm::dvec3 ab, bc, ca;   ///< (a - p) x (b - p) ...: d . ab is the side of edge ab the line passes
    glm::dvec3 normal;       ///< (b - a) x (c - a)
    double sp = 0.0;         ///< normal . (p - a): the side of the plane p lies on

    TriangleSeenFrom() = default;
    TriangleSeenFrom(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
    {
        const glm::dvec3 pa = a - p, pb = b - p, pc = c - p;
        ab = glm::cross(pa, pb), bc = glm::cross(pb, pc), ca = glm::cross(pc, pa);
        normal = glm::cross(b - a, c - a);
        sp = -glm::dot(normal, pa);
    }

    /// Whether the segment p -> p + d crosses the triangle (segmentCrossesTriangle).
    bool crossedBy(const glm::dvec3& d) const
    {
        const double w0 = glm::dot(ab, d), w1 = glm::dot(bc, d), w2 = glm::dot(ca, d);
        if (!((w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0) || (w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0)))
            return false;
        const double sq = sp + glm::dot(normal, d);   // normal . (q - a)
        if (!((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)))
            return false;
        const double t = sp / (sp - sq);
        const double length2 = glm::dot(d, d), margin2 = kEndMarginMetres * kEndMarginMetres;
        return t * t * length2 > margin2 && (1.0 - t) * (1.0 - t) * length2 > margin2;
    }
};

/// Whether segment p -> q crosses triangle (a, b, c), more than kEndMarginMetres (along the
/// segment) from both ends: the contract's test in double precision. Orientation predicates
/// (signed volumes, Plücker products) relative to p; they can only be wrong in sign where the ray
/// passes within rounding (~1e-10 m at 1e6 m) of an edge or an end, which is a tie.
///
/// A ray exactly through an edge counts for the triangle (edges are inclusive), and the edge's
/// predicate is computed from the same two vertices in both triangles that share it, bit for bit
/// negated: so a closed mesh, or a wall of two triangles, has no crack along its shared edges
/// (ties either way would be allowed, but a designer sees a crack in a wall as a bug).
inline bool segmentCrossesTriangle(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b,
                                   const glm::dvec3& c)
{
    return TriangleSeenFrom(p, a, b, c).crossedBy(q - p);
}

} // namespace sightline
