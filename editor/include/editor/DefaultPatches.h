#pragma once
// Where a bare level's patches start: the pair a designer would place first, inside the level,
// over a real floor, facing each other across open space. Plain C++.

#include <utility>

#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline::ui {

/// Patches across a level's box: a source and a receiver of `side` metres, 1.5 m above its lowest
/// point, facing each other along its longer horizontal axis, 32x32 samples each. What a level
/// with no floor to stand on gets, and the start of an empty project.
std::pair<Patch, Patch> defaultPatches(const Bounds& level, double side = 1.0);

/// The pair over the level's floors. Candidates stand at defaultPatches' height over points
/// spread evenly by area over the floors (triangles wound to face up, or down where no triangle
/// faces up), where the floor is the first surface straight below, and with at least half a side
/// (and 10 cm) of clearance up and around. A room's surfaces face into it, so the candidates that
/// see the fewest surfaces from behind are kept (not one inside a solid block or in the void
/// around a Quake map's rooms), and of those the enclosed ones (something above and on every side:
/// inside a room, not on a building's roof) where there are two or more; a terrain has none.
/// Of the pairs with a clear line between centres, the farthest apart; each patch upright, facing
/// the other. A level without candidates, or one Embree cannot hold, keeps defaultPatches' pair.
std::pair<Patch, Patch> defaultPatchesInOpenSpace(const Scene& level, double side = 1.0);

} // namespace sightline::ui
