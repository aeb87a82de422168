#pragma once
// Which points' shadows from one light can change when something inside some boxes changes (an
// occluder moved, added or removed there): those with a shadow segment to one of the light's
// emitters that meets a box. Every other point's segments avoid the boxes, so each of them is
// blocked or free exactly as before, and its field (a sum over those segments) is unchanged.
//
// Conservative: a point is left out only when each of its segments misses every box grown by a
// margin far above rounding. Whole tiles go first, by the segment between the tile's and the
// light's centres against the box grown by their radii, so a change far from a light's shafts
// costs one slab test per tile.

#include <cstdint>
#include <span>
#include <vector>

#include "lighting/DirectLight.h"
#include "lighting/Light.h"
#include "lights/PointTiles.h"
#include "visibility/Scene.h"

namespace sightline::lights {

/// The points (indices into `points`, ascending) of `tiles` one of whose segments to `light` may
/// meet one of the boxes `regions`. A point or spot light's points beyond its range get no light either way and are
/// left out. A directional light's segments are taken as rays against its direction, so a change
/// beyond the scene's bounds, old or new, is met too.
std::vector<std::uint32_t> pointsShadowedThrough(const Light& light, std::span<const Bounds> regions,
                                                 const std::vector<PointTile>& tiles, std::span<const ShadingPoint> points);

} // namespace sightline::lights
