#pragma once
// The openings a view leaks through: the unblocked rays of a hidden-samples map grouped by where
// each passes closest to the level's geometry (a doorway, a window, the space under a table),
// largest group first. Each unblocked ray is followed through a distance grid of the geometry
// between the patches (DistanceGrid.h) to the point of its least clearance, away from its own
// ends (the patches often stand on a floor or a wall); those points, binned into cells as wide as
// the patches' sample spacing (so that neighbouring rays through one opening touch), fall into
// connected groups, one per opening.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"

namespace sightline::suggest {

struct ViewGap {
    glm::dvec3 centre{0.0};            ///< mean of the group's tightest points
    glm::dvec3 min{0.0}, max{0.0};     ///< the box of its cells' mean points: the opening's extent, as far as the rays show it
    std::uint64_t rays = 0;            ///< unblocked rays through it
    double clearance = 0.0;            ///< the largest least-clearance of its rays (about half the opening), m
    std::vector<std::uint64_t> raySample;   ///< up to kGapRaySample of its rays (receiver * sourceCount + source)
};

inline constexpr std::size_t kGapRaySample = 256;
/// The most unblocked rays findViewGaps follows (each is followed through `steps` points).
inline constexpr std::uint64_t kMaxGapRays = std::uint64_t(1) << 22;

struct GapSettings {
    int cells = 128;       ///< voxels along the longest side of the box between the patches
    int steps = 96;        ///< points followed along each ray
};

/// The gaps of `map` (for `source`, `receiver` displaced by `heights`) among `triangles`, most
/// rays first. Empty when every ray is blocked. Throws sightline::Error past kMaxGapRays.
std::vector<ViewGap> findViewGaps(const WorldTriangles& triangles, const Patch& source, const Patch& receiver,
                                  const ReceiverHeights& heights, const HiddenSampleMap& map, const GapSettings& settings = {});

} // namespace sightline::suggest
