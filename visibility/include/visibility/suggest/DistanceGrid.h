#pragma once
// How far each point of a box lies from the nearest triangle, on a voxel grid: triangles are
// clipped to the box and sampled at under half a voxel's spacing into the voxels they touch, then
// an exact Euclidean distance transform (Felzenszwalb & Huttenlocher 2012, one pass per axis)
// gives every voxel's distance to the nearest touched voxel's centre. Good to about a voxel: it
// says where rays pass close to geometry (ViewGaps.h), not whether they hit it.

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline::suggest {

class DistanceGrid {
public:
    /// The box [lo, hi] split into cubes of side `voxel`, at most `maxCells` along an axis (the
    /// voxel grows to fit). Throws sightline::Error for an empty or non-finite box.
    DistanceGrid(const WorldTriangles& triangles, glm::dvec3 lo, glm::dvec3 hi, double voxel, int maxCells = 192);

    /// Metres from `p` to the nearest triangle, to about a voxel; points outside the box take the
    /// nearest voxel's distance.
    double distance(glm::dvec3 p) const;
    double voxel() const { return voxel_; }
    glm::ivec3 cells() const { return cells_; }
    /// The voxel index along each axis of `p` (clamped to the grid).
    glm::ivec3 cellOf(glm::dvec3 p) const;

private:
    std::size_t index(glm::ivec3 c) const { return (std::size_t(c.z) * cells_.y + c.y) * cells_.x + c.x; }
    void mark(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);
    void transform();

    glm::dvec3 lo_{0.0};
    double voxel_ = 1.0;
    glm::ivec3 cells_{1};
    std::vector<float> squared_;   ///< squared distance in voxels, then metres after transform()
};

} // namespace sightline::suggest
