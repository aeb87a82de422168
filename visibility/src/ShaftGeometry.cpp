#include "visibility/ShaftGeometry.h"

#include <algorithm>
#include <cassert>

#include <glm/geometric.hpp>

#include "visibility/RayCastSampler.h"

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
    ClippedPolygon out;
    for (int i = 0; i < polygon.count; ++i) {
        const glm::dvec3& p = polygon.vertices[std::size_t(i)];
        const glm::dvec3& q = polygon.vertices[std::size_t((i + 1) % polygon.count)];
        const double dp = glm::dot(p, normal) - offset, dq = glm::dot(q, normal) - offset;
        if (dp > 0.0)
            out.vertices[std::size_t(out.count++)] = p;
        if ((dp > 0.0) != (dq > 0.0))
            out.vertices[std::size_t(out.count++)] = p + (q - p) * (dp / (dp - dq));
        assert(out.count <= ClippedPolygon::kMaxVertices);
    }
    polygon = out;
}

ShaftFrames::ShaftFrames(const Patch& sourcePatch, const Patch& receiverPatch)
    : source(sourcePatch, receiverPatch.centre()), receiver(receiverPatch, sourcePatch.centre())
{
    // The reference counts a hit at segment parameter t in [eps, 1 - eps]; near an end, that is
    // a distance from the end's plane of eps times the other end's distance. Margins use the
    // smallest such distance (the difference is far below the grazing tolerance).
    double minReceiverD = 1e300, minSourceD = 1e300;
    for (int k = 0; k < 4; ++k) {
        const glm::dvec3 rc = receiverPatch.corner + double(k & 1) * receiverPatch.u + double(k >> 1) * receiverPatch.v;
        const glm::dvec3 sc = sourcePatch.corner + double(k & 1) * sourcePatch.u + double(k >> 1) * sourcePatch.v;
        minReceiverD = std::min(minReceiverD, source.coordinates(rc).z);
        minSourceD = std::min(minSourceD, receiver.coordinates(sc).z);
    }
    sourceMargin = double(kSegmentEpsilon) * minReceiverD;
    receiverMargin = double(kSegmentEpsilon) * minSourceD;
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

} // namespace sightline
