#pragma once
// A bounding-box tree over the scene's triangles for one question: does any triangle come inside a
// shaft (visibility/ShaftGeometry.h's hull of a light and a tile of points)? None does, and every
// segment of the shaft is free: Barczak's "fully lit" class, proved rather than read off a shadow
// map. The hull's test is conservative (a triangle it cannot separate from the shaft by one of its
// face planes counts as inside), so "none inside" is a proof and "some inside" proves nothing.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"
#include "visibility/ShaftGeometry.h"

namespace sightline::lights {

class TriangleBoxTree {
public:
    explicit TriangleBoxTree(const WorldTriangles& triangles);

    /// Whether some triangle may meet the shaft `hull`, whose points span the box [lo, hi].
    bool anyInside(const ShaftHull& hull, const glm::dvec3& lo, const glm::dvec3& hi) const;

private:
    struct Node {
        glm::vec3 lo, hi;
        std::uint32_t first = 0;   ///< leaf: its triangles in order_; inner: the left child (right = first + 1)
        std::uint32_t count = 0;   ///< triangles in a leaf, 0 for an inner node
    };
    void build(std::uint32_t index, std::uint32_t first, std::uint32_t count, const std::vector<glm::vec3>& centres);

    const WorldTriangles& triangles_;
    std::vector<std::uint32_t> order_;
    std::vector<Node> nodes_;
};

} // namespace sightline::lights
