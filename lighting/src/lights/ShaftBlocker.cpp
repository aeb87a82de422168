#include "lights/ShaftBlocker.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "visibility/ExactSegment.h"
#include "visibility/suggest/ConvexHull2.h"

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

/// Plane coordinates of exactly coplanar points: the two axes the plane's normal leans on least,
/// relative to one of its points (so that rounding stays at the scale of the shaft, not of the
/// coordinates).
struct PlaneCoordinates {
    glm::dvec3 origin;
    int i, j;

    PlaneCoordinates(const glm::dvec3& o, const glm::dvec3& normal) : origin(o)
    {
        const glm::dvec3 m = glm::abs(normal);
        const int k = m.x >= m.y && m.x >= m.z ? 0 : m.y >= m.z ? 1 : 2;
        i = (k + 1) % 3, j = (k + 2) % 3;
    }
    glm::dvec2 operator()(const glm::dvec3& x) const { return {x[i] - origin[i], x[j] - origin[j]}; }
};

double orientation(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c)
{
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/// Whether segment pq meets the closed convex polygon `hull` (counter-clockwise).
bool segmentMeetsConvex(const glm::dvec2& p, const glm::dvec2& q, const std::vector<glm::dvec2>& hull)
{
    double lo = 0.0, hi = 1.0;
    for (std::size_t e = 0; e < hull.size(); ++e) {
        const glm::dvec2& a = hull[e];
        const glm::dvec2& b = hull[(e + 1) % hull.size()];
        const double fp = orientation(a, b, p), fq = orientation(a, b, q);   // inside: >= 0
        if (fp < 0.0 && fq < 0.0)
            return false;
        if (fp < 0.0)
            lo = std::max(lo, fp / (fp - fq));
        else if (fq < 0.0)
            hi = std::min(hi, fp / (fp - fq));
        if (lo > hi)
            return false;
    }
    return true;
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

bool coplanarRegionBlocksShaft(const WorldTriangles& triangles, std::span<const std::array<std::int64_t, 3>> neighbours,
                               std::int64_t seed, std::span<const glm::dvec3> from, std::span<const glm::dvec3> to)
{
    constexpr std::size_t kMostTriangles = 256;
    const auto vertex = [&](std::int64_t t, int k) { return glm::dvec3(triangles.vertices[3 * std::size_t(t) + std::size_t(k)]); };
    const glm::dvec3 a = vertex(seed, 0), b = vertex(seed, 1), c = vertex(seed, 2);
    if (from.empty() || to.empty() || !separates(a, b, c, from, to))
        return false;
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const PlaneCoordinates plane(a, n);
    std::vector<glm::dvec2> crossings;
    for (const glm::dvec3& p : from)
        for (const glm::dvec3& q : to)
            crossings.push_back(plane(p + glm::dot(n, a - p) / glm::dot(n, q - p) * (q - p)));
    const std::vector<glm::dvec2> hull = suggest::convexHull(crossings);
    if (hull.size() < 3)
        return false;
    glm::dvec2 lo = hull[0], hi = hull[0], centroid(0.0);
    for (const glm::dvec2& h : hull)
        lo = glm::min(lo, h), hi = glm::max(hi, h), centroid += h;
    centroid /= double(hull.size());
    std::vector<glm::dvec2> inner{centroid};   // points inside K (the centroid may lie on an edge)
    for (const glm::dvec2& h : hull)
        inner.push_back(0.5 * (centroid + h));

    // U: the coplanar triangles joined to the seed that reach K's box.
    std::vector<std::int64_t> region{seed};
    const auto reaches = [&](std::int64_t t) {
        glm::dvec2 tlo(INFINITY), thi(-INFINITY);
        for (int k = 0; k < 3; ++k) {
            if (glm::dot(n, vertex(t, k) - a) != 0.0)
                return false;   // not exactly coplanar
            const glm::dvec2 x = plane(vertex(t, k));
            tlo = glm::min(tlo, x), thi = glm::max(thi, x);
        }
        return tlo.x <= hi.x && thi.x >= lo.x && tlo.y <= hi.y && thi.y >= lo.y;
    };
    const auto inRegion = [&](std::int64_t t) { return std::find(region.begin(), region.end(), t) != region.end(); };
    for (std::size_t r = 0; r < region.size(); ++r)
        for (int e = 0; e < 3; ++e) {
            const std::int64_t other = neighbours[std::size_t(region[r])][std::size_t(e)];
            if (other >= 0 && !inRegion(other) && reaches(other)) {
                if (region.size() == kMostTriangles)
                    return false;
                region.push_back(other);
            }
        }
    // No boundary edge of U meets K, and a point inside K lies inside a triangle of U.
    bool meetsInside = false;
    for (const std::int64_t t : region) {
        const glm::dvec2 v[3] = {plane(vertex(t, 0)), plane(vertex(t, 1)), plane(vertex(t, 2))};
        for (int e = 0; e < 3; ++e) {
            const glm::dvec2& p = v[e];
            const glm::dvec2& q = v[(e + 1) % 3];
            const std::int64_t other = neighbours[std::size_t(t)][std::size_t(e)];
            bool interior = false;
            if (other >= 0 && inRegion(other)) {
                glm::dvec2 across = plane(vertex(other, 0));   // the neighbour's vertex off the shared edge
                for (int k = 1; k < 3; ++k)
                    if (across == p || across == q)
                        across = plane(vertex(other, k));
                const double here = orientation(p, q, v[(e + 2) % 3]), there = orientation(p, q, across);
                interior = (here > 0.0 && there < 0.0) || (here < 0.0 && there > 0.0);
            }
            if (!interior && segmentMeetsConvex(p, q, hull))
                return false;
        }
        for (const glm::dvec2& x : inner) {
            const double s0 = orientation(v[0], v[1], x), s1 = orientation(v[1], v[2], x), s2 = orientation(v[2], v[0], x);
            meetsInside = meetsInside || (s0 > 0.0 && s1 > 0.0 && s2 > 0.0) || (s0 < 0.0 && s1 < 0.0 && s2 < 0.0);
        }
    }
    return meetsInside;
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
