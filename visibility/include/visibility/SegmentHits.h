#pragma once
// Where segments first meet the scene, for drawing: the editor draws a blocked ray only up to
// where it is stopped, with a mark there (issue 16 §2), for the few thousand rays it draws.
//
// Embree's own float triangles and rtcIntersect1, built once per scene. This answers "where",
// never "whether": a ray is blocked when an exact sampler says so (DESIGN.md §2). A blocked ray
// that Embree's float test passes by (a tie at an edge) gets no hit here and is drawn whole.

#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline {

class SegmentHitCaster {
public:
    /// Throws sightline::Error if Embree fails.
    explicit SegmentHitCaster(const WorldTriangles& triangles);
    ~SegmentHitCaster();
    SegmentHitCaster(const SegmentHitCaster&) = delete;
    SegmentHitCaster& operator=(const SegmentHitCaster&) = delete;

    /// The fraction t in (0, 1) of segment from -> to where it first crosses a triangle, or 1
    /// when Embree's float ray meets none strictly between the ends. Rays start at `from`'s own
    /// float position relative to the scene, so kilometre coordinates cost precision (centimetres
    /// at 100 km), which a drawing can afford.
    float firstHit(const glm::dvec3& from, const glm::dvec3& to) const;

private:
    struct Embree;
    std::unique_ptr<Embree> embree_;
};

} // namespace sightline
