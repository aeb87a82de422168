#include "visibility/ShaftGeometry.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "visibility/ExactSegment.h"

namespace sightline {

PatchFrame::PatchFrame(const Patch& patch, const glm::dvec3& towards) : origin(patch.corner)
{
    glm::dvec3 n = patch.normal();
    if (glm::dot(towards - patch.corner, n) < 0.0)
        n = -n;
    // Dual basis of (u, v, n): s = dot(X - c, sAxis) recovers the u-coordinate even when u and v
    // are not orthogonal.
    const glm::dvec3 uv = glm::cross(patch.v, n), vn = glm::cross(n, patch.u);
    sAxis = uv / glm::dot(patch.u, uv);
    tAxis = vn / glm::dot(patch.v, vn);
    dAxis = n;
}

void clipPolygon(ClippedPolygon& polygon, const glm::dvec3& normal, double offset)
{
    std::array<double, ClippedPolygon::kMaxVertices> distance;
    bool allInside = true;
    for (int i = 0; i < polygon.count; ++i) {
        distance[std::size_t(i)] = glm::dot(polygon.vertices[std::size_t(i)], normal) - offset;
        allInside = allInside && distance[std::size_t(i)] > 0.0;
    }
    // Most triangles in a shaft lie wholly between its planes: left as they are, without the
    // copy (a tenth of a swapped bitmask call's setup in profiles went to building `out`).
    if (allInside)
        return;
    ClippedPolygon out;
    for (int i = 0; i < polygon.count; ++i) {
        const int next = (i + 1) % polygon.count;
        const glm::dvec3& p = polygon.vertices[std::size_t(i)];
        const glm::dvec3& q = polygon.vertices[std::size_t(next)];
        const double dp = distance[std::size_t(i)], dq = distance[std::size_t(next)];
        if (dp > 0.0)
            out.vertices[std::size_t(out.count++)] = p;
        // Interpolated from the inside end, whichever way the edge is walked: two triangles
        // sharing the edge then cut it at the same point, bit for bit (no crack between them).
        if (dp > 0.0 && !(dq > 0.0))
            out.vertices[std::size_t(out.count++)] = p + (q - p) * (dp / (dp - dq));
        else if (!(dp > 0.0) && dq > 0.0)
            out.vertices[std::size_t(out.count++)] = q + (p - q) * (dq / (dq - dp));
        assert(out.count <= ClippedPolygon::kMaxVertices);
    }
    polygon = out;
}

ShaftFrames::ShaftFrames(const Patch& sourcePatch, const Patch& receiverPatch)
    : source(sourcePatch, receiverPatch.centre()), receiver(receiverPatch, sourcePatch.centre()),
      sourceMargin(kEndMarginMetres), receiverMargin(kEndMarginMetres)
{
}

ClippedPolygon ShaftFrames::clipToSlab(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const
{
    ClippedPolygon polygon;
    polygon.vertices[0] = glm::dvec3(a);
    polygon.vertices[1] = glm::dvec3(b);
    polygon.vertices[2] = glm::dvec3(c);
    polygon.count = 3;
    clipPolygon(polygon, source.dAxis, glm::dot(source.origin, source.dAxis) + sourceMargin);
    if (polygon.count)
        clipPolygon(polygon, receiver.dAxis, glm::dot(receiver.origin, receiver.dAxis) + receiverMargin);
    return polygon;
}

ShaftHull::ShaftHull(const Patch& source, const Patch& receiver) : ShaftHull([&] {
    std::array<glm::dvec3, 8> corners;
    for (int k = 0; k < 4; ++k) {
        corners[std::size_t(k)] = source.cornerPoint(k);
        corners[std::size_t(k + 4)] = receiver.cornerPoint(k);
    }
    return std::vector<glm::dvec3>(corners.begin(), corners.end());
}())
{
}

ShaftHull::ShaftHull(const std::vector<glm::dvec3>& points)
{
    double scale = 0.0;
    for (const glm::dvec3& c : points)
        scale = std::max(scale, glm::length(c - points[0]));
    const double flat = 1e-9 * scale;
    tolerance_ = 1e-5 * scale;   // a far larger margin than any rounding in the samplers
    // Every plane through three points with all of them on one side is a face plane of the hull
    // (56 triples for the 8 corners: cheap, and no hull algorithm to get wrong).
    for (std::size_t i = 0; i < points.size(); ++i)
        for (std::size_t j = i + 1; j < points.size(); ++j)
            for (std::size_t k = j + 1; k < points.size(); ++k) {
                glm::dvec3 n = glm::cross(points[j] - points[i], points[k] - points[i]);
                const double length = glm::length(n);
                if (length <= 1e-12 * scale * scale)
                    continue;   // collinear (or repeated) points
                n /= length;
                double lo = 1e300, hi = -1e300;
                for (const glm::dvec3& c : points) {
                    const double d = glm::dot(n, c - points[i]);
                    lo = std::min(lo, d), hi = std::max(hi, d);
                }
                if (hi > flat && lo < -flat)
                    continue;   // points on both sides: not a face
                if (hi > flat)
                    n = -n;
                const double offset = glm::dot(n, points[i]);
                const bool known = std::any_of(planes_.begin(), planes_.end(), [&](const Plane& p) {
                    return glm::dot(p.normal, n) > 1.0 - 1e-12 && std::abs(p.offset - offset) <= flat;
                });
                if (!known)
                    planes_.push_back({n, offset});
            }
}

bool ShaftHull::excludes(const glm::dvec3* points, int count) const
{
    for (const Plane& p : planes_) {
        bool allOutside = true;
        for (int i = 0; i < count && allOutside; ++i)
            allOutside = glm::dot(p.normal, points[i]) > p.offset + tolerance_;
        if (allOutside)
            return true;
    }
    return false;
}

bool ShaftHull::excludes(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const
{
    const glm::dvec3 points[3] = {glm::dvec3(a), glm::dvec3(b), glm::dvec3(c)};
    return excludes(points, 3);
}

bool ShaftHull::excludesBox(const glm::vec3& lo, const glm::vec3& hi) const
{
    glm::dvec3 points[8];
    for (int k = 0; k < 8; ++k)
        points[k] = glm::dvec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
    return excludes(points, 8);
}

bool receiverApartFrom(const Bounds& b, const Patch& receiver)
{
    Bounds receiverBox;
    for (int k = 0; k < 4; ++k)
        receiverBox.extend(glm::vec3(receiver.cornerPoint(k)));
    const float pad = 1e-4f * (1.0f + glm::length(receiverBox.max - receiverBox.min));
    return glm::any(glm::lessThan(b.max + pad, receiverBox.min)) || glm::any(glm::greaterThan(b.min - pad, receiverBox.max));
}

} // namespace sightline
