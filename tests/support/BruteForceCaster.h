#pragma once
// An independent reference for tests: every segment against every triangle in double precision
// (Möller-Trumbore), with docs/design.md §2 semantics. Slow, obviously correct, and it also reports
// how close each ray came to an edge or end point, so that comparisons can set aside rays whose
// answer depends on rounding ("grazing" within a stated tolerance).

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "visibility/ExactSegment.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/RayCastSampler.h"
#include "visibility/Scene.h"
#include "visibility/SourceJitter.h"

namespace sightline::test {

struct SegmentResult {
    bool blocked = false;
    /// Smallest distance (metres) by which any triangle's answer could flip: distance of the plane
    /// crossing to the triangle's boundary, or of the crossing to the segment's ends.
    double margin = 1e30;
};

inline SegmentResult bruteForceSegment(const WorldTriangles& tris, const glm::dvec3& from, const glm::dvec3& to)
{
    SegmentResult result;
    const glm::dvec3 d = to - from;
    const double length = glm::length(d);
    const double tMin = kEndMarginMetres / length, tMax = 1.0 - kEndMarginMetres / length;
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const glm::dvec3 a(tris.vertices[3 * t]), b(tris.vertices[3 * t + 1]), c(tris.vertices[3 * t + 2]);
        const glm::dvec3 e1 = b - a, e2 = c - a;
        const glm::dvec3 n = glm::cross(e1, e2);
        const double area2 = glm::length(n);
        if (area2 == 0.0)
            continue;   // degenerate: blocks nothing
        const double denom = glm::dot(n, d);
        const double da = glm::dot(n, from - a), db = glm::dot(n, to - a);
        if (std::abs(denom) < 1e-12 * area2 * length) {
            // Parallel to the plane: only a coplanar segment could touch, which is grazing.
            if (std::abs(da) / area2 < 1e-5)
                result.margin = 0.0;
            continue;
        }
        const double s = -da / denom;   // parameter of the plane crossing
        (void)db;
        const glm::dvec3 p = from + s * d;
        // Signed distances of p to the three edges (positive inside).
        const glm::dvec3 nn = n / area2;
        const double d0 = glm::dot(glm::cross(e1, p - a), nn) / glm::length(e1);
        const double d1 = glm::dot(glm::cross(c - b, p - b), nn) / glm::length(c - b);
        const double d2 = glm::dot(glm::cross(a - c, p - c), nn) / glm::length(a - c);
        const double edge = std::min({d0, d1, d2});
        const bool inside = edge > 0.0;
        const bool within = s > tMin && s < tMax;
        if (inside && within)
            result.blocked = true;
        // How far from flipping: edge distance if the crossing is within the segment, distance to
        // the ends if the crossing is inside the triangle.
        if (s > tMin - 1e-3 && s < tMax + 1e-3)
            result.margin = std::min(result.margin, std::abs(edge));
        if (inside)
            result.margin = std::min({result.margin, std::abs(s - tMin) * length, std::abs(s - tMax) * length});
    }
    return result;
}

struct BruteForceMap {
    HiddenSampleMap blocked;
    HiddenSampleMap grazing;   ///< rays whose margin is below the tolerance
};

inline BruteForceMap bruteForceSample(const WorldTriangles& tris, const Patch& source, const Patch& receiver,
                                      double grazingTolerance = 1e-5, const SourceJitter& jitter = {})
{
    BruteForceMap out{HiddenSampleMap(source.sampleCount(), receiver.na, receiver.nb),
                      HiddenSampleMap(source.sampleCount(), receiver.na, receiver.nb)};
    for (int j = 0; j < receiver.sampleCount(); ++j)
        for (int i = 0; i < source.sampleCount(); ++i) {
            const SegmentResult r =
                bruteForceSegment(tris, receiver.sample(j), source.sample(i) + jitter.shift(source, j));
            if (r.blocked)
                out.blocked.setBlocked(j, i);
            if (r.margin < grazingTolerance)
                out.grazing.setBlocked(j, i);
        }
    return out;
}

/// Rays on which `map` and the brute force disagree, not counting grazing rays.
inline std::uint64_t mismatchesOutsideGrazing(const HiddenSampleMap& map, const BruteForceMap& reference)
{
    std::uint64_t count = 0;
    for (int j = 0; j < map.receiverCount(); ++j)
        for (int i = 0; i < map.sourceCount(); ++i)
            if (!reference.grazing.blocked(j, i) && map.blocked(j, i) != reference.blocked.blocked(j, i))
                ++count;
    return count;
}

} // namespace sightline::test
