#pragma once
// The brute force a user would write with Embree alone: every shadow segment as a float ray over
// Embree's own triangles (its fast native intersector, a high-quality BVH, coherent packets of 16
// from a shared start, kept 1e-4 of the way off each end). It is the yardstick for the exact
// paths' speed, not an answer of the contract: float rounding misjudges segments near edges and
// ends, and far from the origin more than near it.

#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline::lights {

class FloatShadowRays {
public:
    /// Throws sightline::Error if Embree fails.
    explicit FloatShadowRays(const WorldTriangles& triangles);
    ~FloatShadowRays();
    FloatShadowRays(const FloatShadowRays&) = delete;
    FloatShadowRays& operator=(const FloatShadowRays&) = delete;

    /// blocked[k] = 1 where Embree's float ray start -> ends[k] meets a triangle, t in [1e-4, 1 - 1e-4].
    /// Thread-safe.
    void blocked(const glm::dvec3& start, std::span<const glm::dvec3> ends, std::uint8_t* blocked) const;
    /// Likewise for starts[k] -> ends[k]; throws sightline::Error unless there are as many of each.
    void blocked(std::span<const glm::dvec3> starts, std::span<const glm::dvec3> ends, std::uint8_t* blocked) const;

private:
    struct Embree;
    std::unique_ptr<Embree> embree_;
};

} // namespace sightline::lights
