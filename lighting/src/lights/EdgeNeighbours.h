#pragma once
// For each world triangle, the triangle across each of its edges: the one other triangle whose
// edge has the same two float vertices (welded by exact equality). -1 where an edge has no
// neighbour or more than one (a non-manifold edge). ShaftBlocker.h fuses a triangle with such a
// neighbour when the two are coplanar and convex together.

#include <array>
#include <cstdint>
#include <vector>

#include "visibility/Scene.h"

namespace sightline::lights {

/// neighbours[t][e]: the triangle across edge e of triangle t, edge e running from vertex e to
/// vertex (e + 1) % 3.
std::vector<std::array<std::int64_t, 3>> edgeNeighbours(const WorldTriangles& triangles);

} // namespace sightline::lights
