#pragma once
// The furnishing meshes of the generated levels (internal to levelgen/demo): plants, pots, pillars,
// railings, chairs, tables, bookcases, crates, lamps, vases and sofas, each built in its own
// object space (standing on y = 0, facing +z where it has a front) and placed by instances.
//
// All are closed and outward (Mesh::watertight) except the plants, whose leaves are open
// single-triangle surfaces. Same result on every call: randomness comes from fixed seeds.

#include <cstdint>

#include "demo/LevelParts.h"

namespace sightline::demo::parts {

struct PlantShape {
    const char* name;
    std::uint64_t seed;
    float stemTop;      // stem from inside the pot up to here
    vec3 crownCentre;   // leaves fill an ellipsoid here
    vec3 crownRadii;
    int leaves;
    bool hanging;       // hung from the ceiling by cords (origin at the ceiling) instead of a stem
};

/// The demo level's plant shapes (1000 leaves each); a hanging plant's origin is its hook.
inline const PlantShape kFicus{"plant_ficus", 0x51C0FFEEull, 1.25f, {0, 1.45f, 0}, {0.42f, 0.42f, 0.42f}, 1000, false};
inline const PlantShape kFern{"plant_fern", 0xFE4Aull, 0.45f, {0, 0.72f, 0}, {0.55f, 0.3f, 0.55f}, 1000, false};
inline const PlantShape kPalm{"plant_palm", 0xA1A1ull, 1.5f, {0, 1.68f, 0}, {0.5f, 0.32f, 0.5f}, 1000, false};
inline const PlantShape kHanging{"plant_hanging", 0x4A46ull, 0.0f, {0, -1.2f, 0}, {0.3f, 0.45f, 0.3f}, 1000, true};

/// Stem (or cords) plus `leaves` single-triangle leaves 3-8 cm long, random position in the crown
/// ellipsoid and random orientation. Not closed (leaves are open surfaces).
Mesh plant(const PlantShape& s);
Mesh pot();
/// Hanging basket, origin at the ceiling (or the beam it hangs from).
Mesh basket();
/// Turned column on a plinth under an abacus, floor to kCeiling.
Mesh pillar();
/// 2 m railing section along local +x: a post at x = 0, top and bottom rails, 19 turned balusters.
Mesh railing();
Mesh railingPost();
/// Wooden chair facing +z: seat, four legs (the rear ones run up as back posts), three back slats,
/// stretchers.
Mesh chairWood();
/// Bistro chair facing +z: round seat, four turned legs, a curved back of bars.
Mesh chairBistro();
/// Round pedestal table, 1.12 m across.
Mesh tableRound();
/// 2.4 x 0.9 m table on four legs.
Mesh tableLong();
/// Bookcase, back against local -z, 1.2 x 2.0 x 0.35 m; four shelves of books of random size.
Mesh bookcase(const char* name, std::uint64_t seed);
/// Banded crate, `size` m on a side.
Mesh crate(const char* name, float size);
/// Shade, bulb and cord; origin at the ceiling, the shade's rim `drop` + 0.86 m below it.
Mesh pendantLamp(const char* name, float drop);
Mesh vaseOnPlinth();
/// Facing +z, 2.0 m wide.
Mesh sofa();
/// 1.2 x 0.7 m low table with a magazine shelf.
Mesh tableLow();

} // namespace sightline::demo::parts
