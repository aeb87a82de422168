#pragma once
// One-click fixes for an invalid patch pair (docs/design.md §2: each patch entirely on one side of the
// other's plane). The natural pairs fail by centimetres: a patch on a wall that reaches down to the
// floor crosses the plane of a patch lying 2 cm over that floor; a floor patch that runs up to the
// wall crosses a wall patch's plane. Changing one patch alone, the fixes are: move it off the
// other's plane (lift a wall patch above a floor patch), or shrink it to the part on one side.
// Plain C++ (no Qt).

#include <optional>
#include <string>

#include "visibility/Patch.h"

namespace sightline::ui {

struct PatchPairFix {
    bool source = false;          ///< which patch changes: the source (else the receiver)
    Patch patch;                  ///< its new geometry (same samples)
    std::string description;      ///< "lift the receiver 4 cm above the source's plane"
};

/// The margin a fix leaves between a patch and the other's plane.
inline constexpr double kPairFixMargin = 0.01;

/// A fix that makes the pair valid, changing `preferSource`'s patch if one does, else the other's:
/// moving it off the other's plane when that takes at most `maxMove` metres, else shrinking it to
/// one side (keeping at least a fifth of it); the side the other patch faces first, where a patch
/// belongs. nullopt when the pair is valid, a patch is degenerate, or nothing small fixes it.
std::optional<PatchPairFix> fixPatchPair(const Patch& source, const Patch& receiver, bool preferSource, double maxMove = 0.3);

} // namespace sightline::ui
