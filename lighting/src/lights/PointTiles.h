#pragma once
// Shading points grouped into small, compact tiles (Barczak's screen tiles): points sorted along a
// Morton curve over their bounding box and cut into runs of kTilePoints, each with its box. A
// tile's shadow rays to one light leave from nearby points towards one place, so they go in
// coherent packets, and one proof (ShaftBlocker.h) can settle them all.

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/DirectLight.h"

namespace sightline::lights {

inline constexpr std::size_t kTilePoints = 64;

struct PointTile {
    std::vector<std::uint32_t> points;   ///< indices into the caller's points
    glm::dvec3 lo{0.0}, hi{0.0};         ///< their positions' box
};

std::vector<PointTile> makePointTiles(std::span<const ShadingPoint> points);

} // namespace sightline::lights
