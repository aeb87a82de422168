#pragma once
// The openings a set of rays passes through: each ray is followed through a distance grid of the
// geometry around the rays (DistanceGrid.h) to the point of its least clearance, away from its own
// ends (rays often start on a floor or end on the object they reach); those points, binned into
// cells as wide as the rays' spacing (so that neighbouring rays through one opening fall into
// touching cells), form connected groups, one per opening, most rays first.
//
// One mechanism for every place Sightline asks "where does the view leak": the unblocked rays of a
// patch pair (ViewGaps.h) and the reference's witness rays from a PVS cell to an object it culls
// (pvs/PvsReference.h).

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline::suggest {

/// A ray to group: a segment and the caller's name for it (kept in Opening::raySample).
struct OpeningRay {
    glm::dvec3 from{0.0}, to{0.0};
    std::uint64_t id = 0;
};

inline constexpr std::size_t kOpeningRaySample = 256;

struct Opening {
    glm::dvec3 centre{0.0};            ///< mean of the group's tightest points
    glm::dvec3 min{0.0}, max{0.0};     ///< the box of its cells' mean points: the opening's extent, as far as the rays show it
    std::uint64_t rays = 0;            ///< rays through it
    double clearance = 0.0;            ///< the largest least-clearance of its rays (about half the opening), m
    std::vector<std::uint64_t> raySample;   ///< the ids of up to kOpeningRaySample of its rays, in the order given
};

struct OpeningSettings {
    int cells = 128;       ///< voxels along the longest side of the rays' box
    int steps = 96;        ///< points followed along each ray
};

/// The openings `rays` pass through among `triangles`, most rays first. `spacing` (metres) is how
/// far apart neighbouring rays start and end (a patch's sample spacing); groups are joined across
/// at least that. Empty when `rays` is. Throws sightline::Error for non-finite rays.
std::vector<Opening> groupOpenings(const WorldTriangles& triangles, std::span<const OpeningRay> rays, double spacing,
                                   const OpeningSettings& settings = {});

} // namespace sightline::suggest
