#pragma once
// Internal to the CPU bitmask sampler: backprojection (§4) and the exact per-row masks (§5, with
// exact intervals instead of the Hough table) in double precision, one receiver sample at a time.
// Occluders the float kernel cannot take (or cannot prove) come here: vertices near a receiver
// sample's distance, source grids wider than 32 columns, CPUs without AVX2, table mode.

#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "Occluders.h"
#include "Shaft.h"

namespace sightline::bitmask {

/// ORs into `row` the source samples hidden by `occluder` from receiver sample j, on the
/// double-precision `path` (Double or Clip).
void backproject(const Shaft& shaft, const Occluder& occluder, Path path, int j, std::uint64_t* row);

/// The occluder clipped for receiver samples at distance d from the source plane (the parts at
/// or beyond d cannot lie on their segments, Shaft::clipDistance).
ClippedPolygon clippedFor(const Occluder& occluder, double d);

/// The backprojection from receiver point r (source coordinates) of a convex polygon whose
/// vertices all lie in 0 < d < r.d, and the source samples inside it, row by row. `factors` (may
/// be null): each vertex's r.d / (r.d - d), precomputed for parallel patches. Crossings stay
/// within their edge's span of s (a nearly flat edge's slope is rounding noise) and every
/// interval is widened by a hair, relative to itself: far below any tie, far above rounding, so
/// two polygons computing a shared edge from different vertices leave no crack. In table mode
/// (Shaft::table) the Hough table's masks instead (TableMode.h).
void backprojectPolygon(const Shaft& shaft, const glm::dvec3* vertices, int count, const glm::dvec3& r,
                        const glm::dvec2& shift, std::uint64_t* mask, const double* factors);

} // namespace sightline::bitmask
