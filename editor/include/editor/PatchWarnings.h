#pragma once
// What looks wrong with where the patches stand, for the status bar: the pair may be valid and
// still not be what the designer meant. A click on what looked like an inside wall could hit the
// wall's outside face (the section cut hides the inside): the patch landed outside the building,
// below the floor, facing the wall, and the view showed only grey wall without a word. Plain C++.

#include <string>
#include <vector>

#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline::ui {

/// A patch facing a surface closer than this (metres) is called out: it stands against a wall on
/// the wrong side.
inline constexpr double kFacingSurfaceMetres = 0.05;

/// Short phrases, one per finding, naming the patch: "the receiver faces away from the source",
/// "the source faces a surface 2 cm in front of it", "the receiver is outside the level",
/// "the source is below a floor". Empty when nothing looks wrong.
std::vector<std::string> patchWarnings(const WorldTriangles& triangles, const Bounds& level, const Patch& source,
                                       const Patch& receiver);

} // namespace sightline::ui
