#pragma once
// Patch size presets: the openings and silhouettes a designer asks "who sees whom"
// about, so a patch is the size of a doorway or a player without typing edge vectors. Used by the
// properties panel (one undoable resize) and by placement (Create > Placing Size).

#include <optional>
#include <span>
#include <string_view>

#include "visibility/Patch.h"

namespace sightline::ui {

struct PatchPreset {
    std::string_view name;   ///< "Doorway"
    double width = 1.0;      ///< metres, across (horizontal on a wall)
    double height = 1.0;     ///< metres, upwards on a wall
};

/// Doorway 0.9 x 2.1 m, window 1.2 x 1.2 m, player standing 0.6 x 1.8 m, player crouching
/// 0.6 x 1.2 m. Anything else is "custom" (typed in the properties panel).
std::span<const PatchPreset> patchPresets();

/// The preset `patch` has the size of (within a millimetre), if any; its upright edge is its height.
std::optional<std::size_t> presetOf(const Patch& patch);

/// `patch` resized to width x height, its directions and sample grid kept. On an upright patch
/// (a wall's) the height goes to the edge nearer the vertical and the bottom edge stays where it
/// is, so a patch standing on the floor keeps standing on it; a lying patch keeps its centre and
/// takes the width along u.
Patch resizedPatch(const Patch& patch, double width, double height);

} // namespace sightline::ui
