#pragma once
// What ambient occlusion works on: the occluding triangles of a scene in world space, and the
// sample points (position, unit normal) whose visibility towards each light direction is tested.
//
// Sample points are either the mesh vertices (Sattler et al. 2004 §3: per-vertex AO), in the
// scene's instance order, or points on a regular grid over each triangle (AoTexels.h, light-map
// texels for levels whose walls are large faces with few vertices).
//
// Ray origins are offset along the point's normal by `offset` = kAoOffsetRelative times the
// scene's bounding-box diagonal, so a point does not see its own surface as a blocker; every
// filler (exact CPU, Embree, GL, Monte-Carlo reference) uses the same origins.

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline {

inline constexpr double kAoOffsetRelative = 1e-4;

/// World-space indexed triangles of every instance (mirroring transforms keep their winding;
/// winding does not matter for AO: both faces of a triangle block).
struct AoOccluders {
    std::vector<glm::vec3> vertices;
    std::vector<std::uint32_t> indices;   ///< 3 per triangle
    Bounds bounds;

    std::size_t triangleCount() const { return indices.size() / 3; }
    /// The bounding-box diagonal (0 for an empty scene).
    double diagonal() const;
};

AoOccluders aoOccluders(const Scene& scene);

enum class AoPointStatus : std::uint8_t {
    Ok,
    NoFace,       ///< a vertex that belongs to no triangle: no normal, no AO (NaN)
    ZeroNormal,   ///< its normal is zero or not finite (degenerate faces only): no AO (NaN)
};

struct AoPoints {
    std::vector<glm::vec3> positions;   ///< world space, as sampled
    std::vector<glm::vec3> normals;     ///< unit; zero where status is not Ok
    std::vector<AoPointStatus> status;
    std::vector<glm::vec3> origins;     ///< position + offset * normal (set by offsetOrigins)

    std::size_t size() const { return positions.size(); }
    std::size_t count(AoPointStatus s) const;
    /// Fills `origins` with the offset above (call once positions and normals are final).
    void offsetOrigins(double offset);
};

/// Every vertex of every instance, in instance order then the mesh's own vertex order (the
/// `ao --npy` order, docs/design.md §4). The normal is the mesh's own where it has one that is finite
/// and non-zero, otherwise the area-weighted mean of the faces around the vertex, transformed to
/// world space with the inverse transpose.
AoPoints aoVertexPoints(const Scene& scene);

} // namespace sightline
