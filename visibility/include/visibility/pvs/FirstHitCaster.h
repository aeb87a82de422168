#pragma once
// First-hit ray casting over the world triangles (Embree 3, robust traversal): which instance a
// ray meets first. The PVS bake proves a cell sees an object with such a ray (a witness segment
// from a point of the cell to the first triangle it meets, which is the object's), the dense
// reference counts with it, and the pixel error is measured by "rendering" panoramas with it.
//
// This is float32 ray casting, not docs/design.md §2's exact test: a witness may be wrong on a tie
// (a ray grazing an edge within about 1e-5 m). The bake's answer is a sampling of a
// from-region question, whose sampling error is orders of magnitude larger; docs/pvs.md says so.

#include <cstdint>
#include <memory>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline::pvs {

struct RayHit {
    std::int64_t instance = -1;   ///< -1: nothing hit before tfar
    std::int64_t triangle = -1;   ///< index into worldTriangles(scene), -1 with no hit
    float t = 0.0f;               ///< in units of the direction's length
    glm::vec3 normal{0.0f};       ///< geometric normal of the hit triangle (unnormalised, winding's)
};

class FirstHitCaster {
public:
    /// Throws sightline::Error if Embree fails or a coordinate is out of docs/design.md §2's range.
    explicit FirstHitCaster(const Scene& scene);
    ~FirstHitCaster();
    FirstHitCaster(const FirstHitCaster&) = delete;
    FirstHitCaster& operator=(const FirstHitCaster&) = delete;

    /// The first triangle met by origin + t * direction, 0 <= t <= tfar. Thread-safe.
    RayHit cast(const glm::vec3& origin, const glm::vec3& direction, float tfar) const { return cast(origin, direction, 0.0f, tfar); }
    /// The same, from tnear on (the next triangle after one already met).
    RayHit cast(const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar) const;

    std::size_t triangleCount() const;

private:
    struct Embree;
    std::unique_ptr<Embree> embree_;
};

/// Where the segment from -> to first crosses a triangle, as the fraction t in (0, 1) of the way,
/// or 1 when it meets none strictly between its ends (1e-4 of its length is kept off each end: a
/// ray from a patch on a wall starts at the wall). The editor draws a blocked ray up to there.
/// It answers "where", never "whether": a ray is blocked when an exact sampler says
/// so, and one this float test passes by (a tie at an edge) is drawn whole.
float segmentFirstHit(const FirstHitCaster& caster, const glm::dvec3& from, const glm::dvec3& to);

} // namespace sightline::pvs
