#pragma once
// Exact triangle-against-convex-hull tests for the generated levels' checks (which triangles meet a
// shaft, whether a patch stands clear of everything): brute-force hull planes and clipping in double
// precision, independent of the samplers' own culling (ShaftHull is conservative by design).

#include <algorithm>
#include <cstddef>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline::test {

struct HullPlane {
    glm::dvec3 n;   // inside: dot(n, p) <= d
    double d;
};

/// The faces of the convex hull of `points`: every plane through three of them with all points on
/// one side (duplicates are harmless).
inline std::vector<HullPlane> hullPlanes(const std::vector<glm::dvec3>& points)
{
    double scale = 0.0;
    for (const auto& p : points)
        scale = std::max(scale, glm::length(p - points[0]));
    const double eps = 1e-9 * scale;
    std::vector<HullPlane> planes;
    const std::size_t n = points.size();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            for (std::size_t k = j + 1; k < n; ++k) {
                glm::dvec3 normal = glm::cross(points[j] - points[i], points[k] - points[i]);
                if (glm::length(normal) <= 1e-12 * scale * scale)
                    continue;   // collinear
                normal = glm::normalize(normal);
                const double d = glm::dot(normal, points[i]);
                bool below = true, above = true;
                for (const auto& p : points) {
                    const double s = glm::dot(normal, p) - d;
                    below = below && s <= eps;
                    above = above && s >= -eps;
                }
                if (below)
                    planes.push_back({normal, d});
                else if (above)
                    planes.push_back({-normal, -d});
            }
    return planes;
}

/// Sutherland-Hodgman: a triangle meets the convex polytope iff clipping it by every half-space
/// leaves something.
inline bool intersects(const std::vector<HullPlane>& planes, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c)
{
    std::vector<glm::dvec3> poly{a, b, c}, next;
    for (const HullPlane& plane : planes) {
        next.clear();
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const glm::dvec3& p = poly[i];
            const glm::dvec3& q = poly[(i + 1) % poly.size()];
            const double sp = glm::dot(plane.n, p) - plane.d, sq = glm::dot(plane.n, q) - plane.d;
            if (sp <= 0.0)
                next.push_back(p);
            if ((sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0))
                next.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        poly.swap(next);
        if (poly.empty())
            return false;
    }
    return true;
}

/// Indices of the triangles of `w` that meet the convex hull of `points`.
inline std::vector<std::size_t> trianglesInHull(const WorldTriangles& w, const std::vector<glm::dvec3>& points)
{
    const std::vector<HullPlane> planes = hullPlanes(points);
    glm::dvec3 lo(1e30), hi(-1e30);
    for (const auto& p : points)
        lo = glm::min(lo, p), hi = glm::max(hi, p);
    std::vector<std::size_t> hits;
    for (std::size_t t = 0; t < w.size(); ++t) {
        const glm::dvec3 a(w.vertices[3 * t]), b(w.vertices[3 * t + 1]), c(w.vertices[3 * t + 2]);
        if (glm::any(glm::lessThan(glm::max(a, glm::max(b, c)), lo)) ||
            glm::any(glm::greaterThan(glm::min(a, glm::min(b, c)), hi)))
            continue;
        if (intersects(planes, a, b, c))
            hits.push_back(t);
    }
    return hits;
}

inline std::vector<glm::dvec3> corners(const Patch& p)
{
    return {p.corner, p.corner + p.u, p.corner + p.u + p.v, p.corner + p.v};
}

/// The patch thickened by `margin` on both sides (and around its rim).
inline std::vector<glm::dvec3> slab(const Patch& p, double margin)
{
    const glm::dvec3 n = p.normal() * margin;
    const glm::dvec3 du = glm::normalize(p.u) * margin, dv = glm::normalize(p.v) * margin;
    const Patch grown{p.corner - du - dv, p.u + 2.0 * du, p.v + 2.0 * dv, p.na, p.nb};
    std::vector<glm::dvec3> points;
    for (const glm::dvec3& c : corners(grown))
        points.insert(points.end(), {c - n, c + n});
    return points;
}

} // namespace sightline::test
