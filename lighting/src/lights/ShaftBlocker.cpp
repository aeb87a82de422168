#include "lights/ShaftBlocker.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "visibility/ExactSegment.h"

namespace sightline::lights {

namespace {

/// +1 when every point lies beyond the plane by more than kSeparationMetres, -1 when every point
/// lies before it so, else 0.
int side(const glm::dvec3& a, const glm::dvec3& unitNormal, std::span<const glm::dvec3> points)
{
    int sign = 0;
    for (const glm::dvec3& p : points) {
        const double distance = glm::dot(unitNormal, p - a);
        const int here = distance > kSeparationMetres ? 1 : distance < -kSeparationMetres ? -1 : 0;
        if (here == 0 || (sign != 0 && here != sign))
            return 0;
        sign = here;
    }
    return sign;
}

bool separates(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::span<const glm::dvec3> from,
               std::span<const glm::dvec3> to)
{
    const glm::dvec3 normal = glm::cross(b - a, c - a);
    const double length = glm::length(normal);
    if (!(length > 0.0) || !std::isfinite(length))
        return false;
    const glm::dvec3 unit = normal / length;
    const int fromSide = side(a, unit, from), toSide = side(a, unit, to);
    return fromSide != 0 && toSide == -fromSide;
}

} // namespace

bool triangleBlocksShaft(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::span<const glm::dvec3> from,
                         std::span<const glm::dvec3> to)
{
    if (from.empty() || to.empty() || !separates(a, b, c, from, to))
        return false;
    for (const glm::dvec3& p : from) {
        const TriangleSeenFrom seen(p, a, b, c);
        for (const glm::dvec3& q : to)
            if (!seen.crossedBy(q - p))
                return false;
    }
    return true;
}

bool quadBlocksShaft(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d,
                     std::span<const glm::dvec3> from, std::span<const glm::dvec3> to)
{
    const glm::dvec3 n = glm::cross(b - a, c - a);
    if (glm::dot(n, d - a) != 0.0)
        return false;   // not exactly coplanar: no fusion
    // Convex: a and d on opposite sides of bc, b and c on opposite sides of ad.
    const double sa = glm::dot(n, glm::cross(c - b, a - b)), sd = glm::dot(n, glm::cross(c - b, d - b));
    const double sb = glm::dot(n, glm::cross(d - a, b - a)), sc = glm::dot(n, glm::cross(d - a, c - a));
    if (!((sa > 0.0 && sd < 0.0) || (sa < 0.0 && sd > 0.0)) || !((sb > 0.0 && sc < 0.0) || (sb < 0.0 && sc > 0.0)))
        return false;
    if (from.empty() || to.empty() || !separates(a, b, c, from, to))
        return false;
    for (const glm::dvec3& p : from) {
        const TriangleSeenFrom first(p, a, b, c), second(p, d, c, b);
        for (const glm::dvec3& q : to)
            if (!first.crossedBy(q - p) && !second.crossedBy(q - p))
                return false;
    }
    return true;
}

bool triangleBlocksParallel(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::span<const glm::dvec3> starts,
                            std::span<const glm::dvec3> ends)
{
    if (starts.empty() || starts.size() != ends.size() || !separates(a, b, c, starts, ends))
        return false;
    for (std::size_t k = 0; k < starts.size(); ++k)
        if (!segmentCrossesTriangle(starts[k], ends[k], a, b, c))
            return false;
    return true;
}

} // namespace sightline::lights
