#pragma once
// The openings a view leaks through: the unblocked rays of a hidden-samples map grouped by where
// each passes closest to the level's geometry (a doorway, a window, the space under a table),
// largest group first (Openings.h, with the patches' sample spacing as the rays' spacing).

#include <cstdint>
#include <vector>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"
#include "visibility/suggest/Openings.h"

namespace sightline::suggest {

/// The most unblocked rays findViewGaps follows (each is followed through `steps` points).
inline constexpr std::uint64_t kMaxGapRays = std::uint64_t(1) << 22;

/// The gaps of `map` (for `source`, `receiver` displaced by `heights`) among `triangles`, most
/// rays first; each opening's raySample holds ray indices (receiver * sourceCount + source).
/// Empty when every ray is blocked. Throws sightline::Error past kMaxGapRays.
std::vector<Opening> findViewGaps(const WorldTriangles& triangles, const Patch& source, const Patch& receiver,
                                  const ReceiverHeights& heights, const HiddenSampleMap& map, const OpeningSettings& settings = {});

} // namespace sightline::suggest
